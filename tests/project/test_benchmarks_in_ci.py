"""Every benchmark script runs at a tiny size in CI, so none rots (issue 35)."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_every_benchmark_script_is_run_by_ci():
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    loop = re.search(r"for bench in (.*?); do", ci, re.S)
    assert loop is not None
    looped = set(loop.group(1).replace("\\", " ").split())
    named = set(re.findall(r"python benchmarks/(\w+)\.py", ci))
    scripts = {p.stem for p in (ROOT / "benchmarks").glob("*.py")}
    assert scripts <= looped | named, sorted(scripts - looped - named)
    for stem in looped:
        assert "--tiny" in (ROOT / "benchmarks" / f"{stem}.py").read_text(encoding="utf-8"), stem
