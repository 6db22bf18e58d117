import pytest


@pytest.fixture
def run_cli(capsys):
    """Run ``vorobound`` in-process; return (exit code, stdout, stderr)."""
    from vorobound.cli import main

    def run(*args: str):
        code = main(list(args))
        captured = capsys.readouterr()
        return code, captured.out, captured.err

    return run


@pytest.fixture(autouse=True)
def _fresh_warnings():
    """Each test sees every once-per-process warning (vorobound.errors.warn_once) afresh."""
    from vorobound.errors import forget_warnings

    forget_warnings()
    yield
