"""CITATION.cff cites the software at its current version and the paper it reproduces."""

from __future__ import annotations

from pathlib import Path

import pytest

import tensegrity_rigidity

yaml = pytest.importorskip("yaml")

CFF = Path(__file__).resolve().parents[1] / "CITATION.cff"


def test_citation_names_the_version_and_the_paper_with_its_authors():
    data = yaml.safe_load(CFF.read_text())
    assert data["cff-version"] == "1.2.0" and data["type"] == "software"
    assert str(data["version"]) == tensegrity_rigidity.__version__
    (paper,) = data["references"]
    assert paper["title"] == "Rigidity of generic random tensegrity structures"
    names = [a["family-names"] for a in paper["authors"]]
    assert names == ["Sudhakar", "McInerney", "Rocklin", "Stephenson"]
    assert "doi" not in paper  # none is known; an invented one would mislead
