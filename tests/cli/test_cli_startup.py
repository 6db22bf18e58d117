"""``vorobound --help`` stays light: no numpy, scipy, matplotlib or numba."""

import subprocess
import sys

PROBE = (
    "import sys\n"
    "from vorobound.cli import main\n"
    "code = main(['--help'])\n"
    "heavy = [m for m in ('numpy', 'scipy', 'matplotlib', 'numba') if m in sys.modules]\n"
    "print('HEAVY=' + ','.join(heavy))\n"
    "sys.exit(code)\n"
)


def test_importing_the_package_is_light_and_names_load_lazily():
    probe = (
        "import sys, vorobound\n"
        "light = 'numpy' not in sys.modules\n"
        "vorobound.weighted_triangles\n"
        "print(light, 'numpy' in sys.modules)\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["True", "True"]


def test_every_command_help_imports_no_heavy_library():
    import vorobound.cli

    commands = [c.name for c in vorobound.cli.app.registered_commands]
    probe = (
        "import sys\n"
        "from vorobound.cli import main\n"
        f"codes = [main([name, '--help']) for name in {commands!r}]\n"
        "heavy = [m for m in ('numpy', 'scipy', 'matplotlib', 'numba') if m in sys.modules]\n"
        "print('CODES=' + ','.join(map(str, codes)) + ' HEAVY=' + ','.join(heavy))\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().endswith(" HEAVY="), done.stdout[-300:]


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
