"""Every number block in the README and docs/*.md is what its example prints today."""

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import update_docs  # noqa: E402

SLOW_EXAMPLES = {
    "lfs_points",
    "lfs_accuracy",
    "samples_table",
    # 2–4 CPU-s each; the code they run is covered by fast tests (named here):
    "lfs_speed",  # estimate_lfs on tori and icospheres: tests/sampling/lfs/test_lfs.py
    "lfs_agreement",  # coarse/fine bar and cube: test_lfs_cad.py::test_coarse_and_fine_*
    "cheng_table",  # cheng_constants(0.3, 2 and 3): tests/studies/test_cheng.py
    "reproduce_table",  # reproduce(QualityParams()): test_printed_numbers.py, `reproduce`
}
"""Examples whose check takes several seconds (run with -m slow, as CI does)."""
CASES = [
    pytest.param(
        doc, name, block, marks=[pytest.mark.slow] if Path(name).stem in SLOW_EXAMPLES else []
    )
    for doc in update_docs.documents()
    for name, block in update_docs.blocks(doc.read_text())
]


def test_the_docs_have_example_blocks():
    assert {case.values[1] for case in CASES} >= {
        "docs/examples/reproduce_table.py",
        "docs/examples/core_snippet.py",
    }


@pytest.mark.parametrize(
    "doc, name, block", CASES, ids=[f"{c.values[0].name}:{Path(c.values[1]).stem}" for c in CASES]
)
def test_block_matches_its_example(doc, name, block):
    module = update_docs.load(name)
    if hasattr(module, "quick_check"):
        module.quick_check(block)
    else:
        assert block == module.render(), f"{doc.name} is stale: run python scripts/update_docs.py"


def test_the_api_page_is_current():
    """docs/api.md is what scripts/api_docs.py generates from today's docstrings."""
    import api_docs

    page = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    assert page == api_docs.render(), "docs/api.md is stale: run python scripts/api_docs.py"
    for name in ("solve", "check", "sample", "advise", "lfs", "certify", "bound"):
        assert f"## `vorobound.{name}`" in page
