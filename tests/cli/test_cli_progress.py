"""Progress without a terminal: plain lines on stderr for long tasks, nothing for short ones."""

from vorobound.cli import progress as cli_progress


def test_redirected_progress_prints_lines_only_for_long_runs(monkeypatch, capsys):
    with cli_progress.progress_bar() as report:  # pytest's stderr is not a terminal
        report("sampling (slabs)", 0, 40)
        report("sampling (slabs)", 1, 40)
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(cli_progress, "PLAIN_SECONDS", 0.0)
    with cli_progress.progress_bar() as report:
        report("sampling (slabs)", 7, 40)
        report("lattice", 3, None)
    assert capsys.readouterr().err.splitlines() == [
        "progress: sampling (slabs) 7/40",
        "progress: lattice 3",
    ]


def test_json_runs_draw_no_progress(capsys):
    with cli_progress.progress_bar(enabled=False) as report:
        report("sampling (slabs)", 7, 40)
    assert capsys.readouterr().err == ""
