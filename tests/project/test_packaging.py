"""The package a scientific Python user expects: license, metadata, type hints in the wheel,
citation, changelog, and ignored output folders."""

import re
import zipfile
from pathlib import Path

import pytest

import vorobound

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: the TOML reader setuptools depends on
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
PAPER_TITLE = (
    "Analytic formula for the difference of the circumradius and orthoradius of a weighted triangle"
)


def _project() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def _version(text: str) -> tuple[int, ...]:
    return tuple(int(part) for part in text.split("."))


def test_license_files_are_the_licenses_pyproject_declares():
    project = _project()
    assert project["license"] == "MIT AND BSD-3-Clause"  # geogram's module is compiled in
    assert project["license-files"] == ["LICENSE", "native/geogram/LICENSE"]
    assert (
        (ROOT / "native/geogram/LICENSE")
        .read_text(encoding="utf-8")
        .startswith("BSD 3-Clause License")
    )
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License")
    assert "Copyright (c) the vorobound developers" in text
    assert "WITHOUT WARRANTY OF ANY KIND" in text


def test_metadata_a_user_expects():
    project = _project()
    classifiers = project["classifiers"]
    assert "Typing :: Typed" in classifiers  # true only while py.typed ships (below)
    assert "Intended Audience :: Science/Research" in classifiers
    assert not [c for c in classifiers if c.startswith("License ::")]  # the SPDX license says it
    tested = [c.rsplit(" :: ", 1)[-1] for c in classifiers if re.search(r"Python :: 3\.\d+$", c)]
    floor = project["requires-python"].removeprefix(">=")
    assert tested and all(
        tuple(map(int, v.split("."))) >= tuple(map(int, floor.split("."))) for v in tested
    )
    assert project["authors"] == [{"name": "the vorobound developers"}]
    assert "urls" not in project or all(
        url.startswith("https://") for url in project["urls"].values()
    )


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> zipfile.ZipFile:
    """The wheel setuptools builds from this checkout (the build backend pyproject names; it
    compiles the native module, about 25 CPU-s: the tests using it are slow)."""
    import os
    import subprocess
    import sys

    pytest.importorskip("setuptools", reason="needs the test extra")
    out = tmp_path_factory.mktemp("wheel")
    build = tmp_path_factory.mktemp("build")
    code = (
        "import sys; from setuptools import build_meta; print(build_meta.build_wheel(sys.argv[1]))"
    )
    env = {**os.environ, "TMPDIR": str(build)}
    done = subprocess.run(
        [sys.executable, "-c", code, str(out)], cwd=ROOT, env=env, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr[-2000:]
    built = list(out.glob("*.whl"))
    assert len(built) == 1
    with zipfile.ZipFile(built[0]) as archive:
        yield archive


@pytest.mark.slow
def test_wheel_ships_type_hints_license_and_classifiers(wheel):
    names = wheel.namelist()
    assert [n for n in names if re.fullmatch(r"vorobound/sampling/_geogram\..*\.so", n)]
    assert not [n for n in names if n.startswith("native/")]
    assert "vorobound/py.typed" in names
    assert "vorobound/cli/__init__.py" in names
    assert not [n for n in names if n.startswith("tests/") or "__pycache__" in n]
    info = next(n.split("/")[0] for n in names if n.endswith(".dist-info/METADATA"))
    assert f"{info}/licenses/LICENSE" in names
    metadata = wheel.read(f"{info}/METADATA").decode()
    assert "License-Expression: MIT AND BSD-3-Clause" in metadata
    assert f"{info}/licenses/native/geogram/LICENSE" in names
    assert "Classifier: Typing :: Typed" in metadata
    assert f"Version: {vorobound.__version__}" in metadata
    assert (ROOT / "vorobound" / "py.typed").is_file()


def test_citation_file_cites_the_paper_by_title_and_the_software():
    yaml = pytest.importorskip("yaml", reason="needs the test extra")
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert citation["cff-version"] == "1.2.0"
    for key in ("message", "title", "authors"):  # required by CFF 1.2.0
        assert citation[key]
    assert citation["type"] == "software"
    assert str(citation["version"]) == _project()["version"] == vorobound.__version__
    assert citation["license"] == _project()["license"].split(" AND ")[0]  # vorobound's own
    papers = [ref for ref in citation["references"] if ref["title"] == PAPER_TITLE]
    assert len(papers) == 1
    for ref in citation["references"]:
        assert {"type", "title", "authors"} <= ref.keys()
        assert all("name" in a or "family-names" in a for a in ref["authors"])
    for author in citation["authors"]:
        assert "name" in author or "family-names" in author
    # the README cites the same title
    assert PAPER_TITLE in " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())


def test_changelog_has_the_released_version_and_an_unreleased_one_above_it():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    versions = re.findall(r"^## (\d+\.\d+\.\d+)", text, flags=re.MULTILINE)
    assert _project()["version"] in versions
    key = [_version(v) for v in versions]
    assert key == sorted(key, reverse=True), "newest first"
    assert "`delta`" in text and "`radius_gap`" in text  # the deprecated JSON key is announced


def test_default_output_folders_are_ignored_by_git():
    from vorobound.api.figures import DEFAULT_OUT

    ignored = {
        line.strip().strip("/")
        for line in (ROOT / ".gitignore").read_text(encoding="utf-8").splitlines()
        if line.strip() and not line.startswith("#")
    }
    docs = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    text = "\n".join(doc.read_text(encoding="utf-8") for doc in docs)
    examples = set(re.findall(r"vorobound (?:check|reconstruct) [^`\n]*--out ([a-z][\w-]*)", text))
    assert examples, "the docs show no check --out folder"
    for folder in {str(DEFAULT_OUT), *examples} - {"figures"}:  # figures/ is committed
        assert folder in ignored, folder
