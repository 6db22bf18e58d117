"""``vorobound --help`` stays light: no scipy, no matplotlib, no numba."""

import subprocess
import sys

PROBE = (
    "import sys\n"
    "from vorobound.cli import main\n"
    "code = main(['--help'])\n"
    "heavy = [m for m in ('scipy', 'matplotlib', 'numba') if m in sys.modules]\n"
    "print('HEAVY=' + ','.join(heavy))\n"
    "sys.exit(code)\n"
)


def test_help_imports_no_heavy_library():
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


def test_one_triangle_does_not_load_numba():
    probe = (
        "import sys\n"
        "from vorobound.cli import main\n"
        "code = main(['triangle', '-p', '0,0,0', '-p', '1,0,0', '-p', '0,1,0', '--json'])\n"
        "print('NUMBA=' + str('numba' in sys.modules))\n"
        "sys.exit(code)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "NUMBA=False" in done.stdout
