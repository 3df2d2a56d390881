"""How long each scale of ``reproduce`` takes: plain text, importable without the numerical
stack, so that the command line's help shows it at once."""

from __future__ import annotations

#: wall times of each scale on 2 cores of the reference machine: measured where stated, else the
#: estimate of :mod:`~tensegrity_rigidity.paper.budget` (``reproduce --estimate``; the tests keep
#: the two in step) until someone times a run
EXPECTED = {
    "tiny": "2.7 to 4.3 minutes measured beside other jobs (load 3 to 10 on 2 cores; 1.7 CPU "
    "minutes), estimated 2 minutes",
    "quick": "8 min 33 s measured from a clean clone, install included (estimated 8 minutes)",
    "paper": "33 min 12 s measured from a clean clone (estimated 33 minutes)",
    "fss": "97 minutes measured in one run, energy grids included (estimated 119 minutes); "
    "resumable: re-run to continue",
    "pc": "the rods-only study by the pebble game (n = 32 to 512; p_c, nu, fractal dimensions): "
    "7 minutes measured on 2 idle cores (estimated 19 minutes)",
    "3d": "beyond the paper, the disordered FCC lattice in 3D (n = 4 to 10, rods-only "
    "thresholds to 12): 74 minutes measured in three invocations beside other runs (load 10 to "
    "20 on 2 cores; estimated 29 minutes)",
    "tiny-3d": "the 3D study at n = 2, 3, 4 with a few samples: about 15 seconds",
    "fss-cluster": "for a Dask cluster (--scheduler): fss plus n = 128, estimated 62 CPU hours "
    "(--estimate --workers N gives the wall time on N workers)",
}
