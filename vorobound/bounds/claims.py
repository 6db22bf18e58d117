"""How strong each bound's claim is: the words the whole package uses, defined once.

* ``proven``: an algebraic proof in the docs (the rigorous chain: docs/errata.md; the tight
  closed form where docs/tight.md covers the parameters);
* ``certified``: a computer-checked interval certificate (``vorobound certify``);
* ``numerical``: optimizer evidence without proof (the tight optimizer);
* ``invalid``: the paper's printed chain, which has a wrong step (docs/errata.md E4).
"""

from __future__ import annotations

PROVEN = "proven"
CERTIFIED = "certified"
NUMERICAL = "numerical"
INVALID = "invalid"

EXPLANATION = {
    PROVEN: "proven (algebraic proof in the docs)",
    CERTIFIED: "certified (interval-arithmetic certificate, re-checkable)",
    NUMERICAL: "numerical (optimizer evidence, not a proof)",
    INVALID: "invalid (the printed chain has a wrong step, docs/errata.md E4)",
}

CHAIN_CLAIM = {"paper": INVALID, "rigorous": PROVEN}
"""The claim of each chain mode."""
