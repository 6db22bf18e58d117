"""``vorobound --help`` stays light: no scipy, no matplotlib."""

import subprocess
import sys

PROBE = (
    "import sys\n"
    "from vorobound.cli import main\n"
    "code = main(['--help'])\n"
    "heavy = [m for m in ('scipy', 'matplotlib') if m in sys.modules]\n"
    "print('HEAVY=' + ','.join(heavy))\n"
    "sys.exit(code)\n"
)


def test_help_imports_neither_scipy_nor_matplotlib():
    done = subprocess.run(
        [sys.executable, "-c", PROBE], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "HEAVY=\n" in done.stdout


def test_python_dash_m_entry_point():
    done = subprocess.run(
        [sys.executable, "-m", "vorobound", "triangle", "--edges", "3,4,5", "--json"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert '"circumradius": 2.5' in done.stdout
