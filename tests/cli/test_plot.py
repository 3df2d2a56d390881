"""``tensegrity-rigidity solve FILE --plot FIGURE`` and the drawing behind it."""

from __future__ import annotations

import json

import matplotlib
import numpy as np
import pytest
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.quiver import Quiver

from tensegrity_rigidity import Element, InputError, lattice_instance, save_instance, solve
from tensegrity_rigidity.cli.main import main
from tensegrity_rigidity.paper.plotting import KIND_COLOURS, draw_network, plot_solution


@pytest.fixture(scope="module")
def mixed():
    """A rigid sample with rods, cables and struts, and its solution."""
    inst = lattice_instance(8, p_r=0.6, p_t=0.35, f_c=0.5, phi="shear", seed=3)
    res = solve(inst)
    assert res.rigid and inst.network.count(Element.STRUT) and inst.network.count(Element.CABLE)
    return inst, res


def test_solve_plot_writes_a_png_and_keeps_json_on_stdout(tmp_path, capsys, mixed):
    inst, _ = mixed
    save_instance(tmp_path / "s.npz", inst)
    fig = tmp_path / "net.png"
    assert main(["solve", str(tmp_path / "s.npz"), "--json", "--plot", str(fig)]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out)["status"] == "rigid"
    assert f"wrote {fig}" in err
    data = fig.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000


def test_solve_plot_svg_of_a_floppy_sample_draws_its_displacements(tmp_path, capsys):
    inst = lattice_instance(6, p_r=0.3, phi="dilation", seed=1)
    save_instance(tmp_path / "f.npz", inst)
    fig = tmp_path / "f.svg"
    assert main(["solve", str(tmp_path / "f.npz"), "--plot", str(fig)]) == 0
    assert "floppy" in capsys.readouterr().out
    assert fig.read_text().lstrip().startswith("<?xml")


@pytest.mark.parametrize(
    "name, message",
    [
        ("net.xyz", "cannot write a figure of format 'xyz'"),
        ("missing/net.png", "does not exist"),
        ("", "empty"),
    ],
)
def test_bad_figure_path_is_one_line_before_solving(tmp_path, capsys, name, message):
    inst = lattice_instance(4, p_r=0.9, seed=0)
    save_instance(tmp_path / "s.npz", inst)
    target = str(tmp_path / name) if name else ""
    assert main(["solve", str(tmp_path / "s.npz"), "--plot", target]) == 2
    out, err = capsys.readouterr()
    assert out == ""  # refused before the solve printed anything
    assert err.startswith("error: ") and message in err and err.count("\n") == 1


def test_pgf_without_tex_is_refused_before_solving(tmp_path, capsys, monkeypatch):
    """``--plot fig.pgf`` ended in "RuntimeError: 'xelatex' not found" after the solve."""
    import shutil

    monkeypatch.setattr(shutil, "which", lambda name: None)
    save_instance(tmp_path / "s.npz", lattice_instance(4, p_r=0.9, seed=0))
    assert main(["solve", str(tmp_path / "s.npz"), "--plot", str(tmp_path / "f.pgf")]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "cannot write a figure of format 'pgf'" in err


def test_figure_path_that_is_a_directory_is_refused(tmp_path, capsys):
    inst = lattice_instance(4, p_r=0.9, seed=0)
    save_instance(tmp_path / "s.npz", inst)
    assert main(["solve", str(tmp_path / "s.npz"), "--plot", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err


def _collections(ax):
    return [c for c in ax.collections if isinstance(c, LineCollection)]


def test_line_width_grows_with_the_tension(mixed):
    inst, res = mixed
    ax = Figure().subplots()
    draw_network(ax, inst, res, colour="kind", arrows=False, widths=(1.0, 5.0))
    kinds = inst.network.kinds
    rods = np.flatnonzero(kinds == Element.ROD)
    rod_lines = next(c for c in _collections(ax) if len(c.get_segments()) == rods.size)
    lw = np.asarray(rod_lines.get_linewidths())
    t = np.abs(res.tensions[rods])
    assert lw.argmax() == t.argmax()
    top = np.abs(res.tensions).max()
    assert lw.min() >= 1.0 and lw.max() == pytest.approx(1.0 + 4.0 * t.max() / top)
    assert np.corrcoef(lw, t)[0, 1] > 0.999


def test_colours_by_kind_and_by_tension(mixed):
    inst, res = mixed
    ax = Figure().subplots()
    draw_network(ax, inst, res, colour="kind", arrows=False)
    cable = matplotlib.colors.to_rgba(KIND_COLOURS[Element.CABLE])
    n_cables = inst.network.count(Element.CABLE)
    cables = next(c for c in _collections(ax) if len(c.get_segments()) == n_cables)
    assert np.allclose(cables.get_colors()[0], cable)
    ax = Figure().subplots()
    draw_network(ax, inst, res, colour="tension", arrows=False)
    cables = next(c for c in _collections(ax) if len(c.get_segments()) == n_cables)
    taut = res.tensions[inst.network.kinds == Element.CABLE] > 0
    red = cables.get_colors()[taut]
    assert np.all(red[:, 0] > red[:, 2])  # pulling cables lean red, never blue


def test_struts_are_hollow_and_empty_sites_are_not_drawn(mixed):
    inst, res = mixed
    ax = Figure().subplots()
    draw_network(ax, inst, res, arrows=False)
    drawn = sum(len(c.get_segments()) for c in _collections(ax))
    net = inst.network
    assert drawn == net.count(Element.ROD) + net.count(Element.CABLE) + 2 * net.count(Element.STRUT)


def test_displacements_are_arrows(mixed):
    inst, res = mixed
    ax = Figure().subplots()
    draw_network(ax, inst, res)
    (q,) = [c for c in ax.collections if isinstance(c, Quiver)]
    assert q.N == inst.network.n_nodes
    ax = Figure().subplots()
    draw_network(ax, inst, res, arrows=False)
    assert not [c for c in ax.collections if isinstance(c, Quiver)]


def test_result_of_another_instance_and_bad_colour_are_refused(mixed, tmp_path):
    inst, res = mixed
    other = lattice_instance(5, p_r=0.9, seed=0)
    with pytest.raises(InputError, match="does not belong"):
        draw_network(Figure().subplots(), other, res)
    with pytest.raises(InputError, match="colour"):
        draw_network(Figure().subplots(), inst, res, colour="rainbow")
    with pytest.raises(InputError, match="format"):
        plot_solution(inst, res, tmp_path / "x.unknown")


def test_a_3d_sample_is_drawn_as_its_three_projections(tmp_path, capsys):
    inst = lattice_instance(3, 0.6, 0.3, phi="compression", lattice="fcc", seed=2)
    save_instance(tmp_path / "f.npz", inst)
    out = tmp_path / "f.png"
    assert main(["solve", str(tmp_path / "f.npz"), "--plot", str(out)]) == 0
    assert out.stat().st_size > 10_000
    res = solve(inst)
    labels = []
    for plane in ((0, 1), (0, 2), (1, 2)):
        ax = Figure().subplots()
        draw_network(ax, inst, res, plane=plane, colorbar=False)
        labels.append((ax.get_xlabel(), ax.get_ylabel()))
        drawn = sum(len(c.get_segments()) for c in ax.collections if isinstance(c, LineCollection))
        # struts are drawn twice (outline and core)
        net = inst.network
        assert drawn == net.count(Element.ROD) + net.count(Element.CABLE) + 2 * net.count(
            Element.STRUT
        )
    assert labels == [("x", "y"), ("x", "z"), ("y", "z")]
    with pytest.raises(InputError, match="plane"):
        draw_network(Figure().subplots(), inst, res, plane=(0, 3))


def _colours(collection) -> set[str]:
    return {matplotlib.colors.to_hex(c) for c in collection.get_colors()}


def test_rods_only_clusters_are_coloured_with_stressed_sites_thicker():
    from tensegrity_rigidity import rigid_clusters
    from tensegrity_rigidity.paper import plotting

    inst = lattice_instance(10, p_r=0.75, seed=4)
    cl = rigid_clusters(inst)
    assert cl.wraps and cl.overconstrained.any() and not cl.overconstrained.all()
    ax = Figure().subplots()
    plotting.draw_clusters(ax, inst.network, cl)
    layers = {next(iter(_colours(c))): c for c in _collections(ax)}
    palette = {c.lower() for c in plotting.OKABE_ITO} | {plotting.LONE_COLOUR.lower()}
    assert set(layers) <= palette  # colour-blind safe
    assert plotting.SPANNING_COLOUR.lower() in layers
    assert plotting.STRESSED_COLOUR.lower() in layers
    stressed = layers[plotting.STRESSED_COLOUR.lower()]
    # every overconstrained rod of the spanning cluster, and only those, drawn stressed
    labels = cl.labels
    big = np.bincount(labels[cl.overconstrained]).argmax()
    want = int(np.sum(cl.overconstrained & (labels == big)))
    assert len(stressed.get_segments()) == want
    assert min(stressed.get_linewidths()) > max(
        layers[plotting.SPANNING_COLOUR.lower()].get_linewidths()
    )
    drawn = sum(len(c.get_segments()) for c in _collections(ax))
    assert drawn == inst.network.count(Element.ROD)  # each rod once, empty sites not at all


def test_solve_plot_of_a_rods_only_sample_adds_its_rigid_clusters(tmp_path, capsys):
    from tensegrity_rigidity.paper import plotting

    inst = lattice_instance(8, p_r=0.8, phi="shear", seed=2)
    captured = {}

    def keep(self, fname, *args, **kwargs):
        captured["fig"] = self
        open(fname, "wb").close()  # (the command renames what was written into place)

    fig_path = tmp_path / "rods.png"
    save_instance(tmp_path / "r.npz", inst)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Figure, "savefig", keep)
        assert main(["solve", str(tmp_path / "r.npz"), "--plot", str(fig_path)]) == 0
    axes = [a for a in captured["fig"].axes if a.get_label() != "<colorbar>"]
    assert len(axes) == 2 and "rigid clusters (pebble game)" in axes[1].get_title()
    colours = set().union(*(_colours(c) for c in _collections(axes[1])))
    assert plotting.STRESSED_COLOUR.lower() in colours
    # a sample with cables keeps the single drawing
    assert not plotting._rods_only(lattice_instance(8, p_r=0.6, p_t=0.3, seed=1).network)


def test_kind_and_tension_colours_are_colour_blind_safe():
    from tensegrity_rigidity.paper import plotting

    palette = {c.lower() for c in plotting.OKABE_ITO}
    assert {matplotlib.colors.to_hex(c) for c in KIND_COLOURS.values()} <= palette
    ends = {matplotlib.colors.to_hex(plotting.TENSION_CMAP(x)) for x in (0.0, 1.0)}
    assert ends == {plotting.BLUE.lower(), plotting.VERMILLION.lower()}
