import os

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


def _cpu_seconds() -> float:
    """CPU seconds (user + system) of this process and of its children that have ended."""
    import resource

    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    """With ``VOROBOUND_TEST_CPU=FILE``, append each test's CPU seconds (setup, call and
    teardown, its child processes included) to FILE: the suite's CPU budget is counted per
    test, which wall durations on a shared machine do not show."""
    target = os.environ.get("VOROBOUND_TEST_CPU")
    if not target:
        yield
        return
    before = _cpu_seconds()
    yield
    with open(target, "a", encoding="utf-8") as out:
        out.write(f"{_cpu_seconds() - before:.3f} {item.nodeid}\n")
