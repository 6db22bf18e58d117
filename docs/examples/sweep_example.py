"""The README's sweep example: the CLI's CSV output, exactly as printed."""

import contextlib
import io

ARGS = ["sweep", "--rho-f", "1.2:1.5:4", "--mode", "rigorous,tight", "--format", "csv"]


def render() -> str:
    from vorobound.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(ARGS) == 0
    return f"```\n$ vorobound {' '.join(ARGS)}\n{out.getvalue()}```\n"


if __name__ == "__main__":
    print(render(), end="")
