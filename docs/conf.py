"""Sphinx configuration of the tensegrity-rigidity documentation.

Build (warning-free, as the test suite does)::

    sphinx-build -W --keep-going -b html docs docs/_build/html

The tutorial notebook (tutorial.ipynb) is executed on every build, so the pages always show
what the current code computes.
"""

from __future__ import annotations

import tensegrity_rigidity

project = "tensegrity-rigidity"
author = "the tensegrity-rigidity developers"
copyright = "the tensegrity-rigidity developers, MIT licence"
release = tensegrity_rigidity.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_nb",
]

exclude_patterns = ["_build", "jupyter_execute", "**.ipynb_checkpoints"]

# --- autodoc, numpydoc --------------------------------------------------------------------
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "none"  # the numpydoc sections carry the types and shapes
autosummary_generate = False  # the API pages are written out, nothing is generated
numpydoc_show_class_members = False  # autodoc documents the members
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# --- MyST, notebooks -----------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
nb_execution_mode = "force"  # run the tutorial on every build
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True

# --- HTML ----------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"tensegrity-rigidity {release}"


def _skip_top_level_exports(app, what, name, obj, skip, options):
    """In a module's page, leave out what the top level exports: it is documented there."""
    if what == "module" and name in tensegrity_rigidity.__all__:
        if getattr(tensegrity_rigidity, name, None) is obj:
            return True
    return None


def setup(app):
    app.connect("autodoc-skip-member", _skip_top_level_exports)
