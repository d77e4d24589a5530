"""One naming rule for theories in summary.json (docs/guide/command_line.md): a value X that has a
closed form sits beside X_theory (same unit, same sign convention), and where the closed form does
not apply to the run X_theory is null with its reason under "undefined". No other spelling
(X_theory_deg, X_closed_form, theory_X, X_expected, X_mean beside X_theory).

Checked on the summaries of short Exudyn runs of the block, particle, capstan, feeder and fastening
scenes: each scene once where its theory applies and, where it has one, once where it does not."""
import math
import warnings

import pytest

from exu_aniso.catalog import MODELS
from exu_aniso.engines.energy import EnergyWarning

# (scene, parameter overrides, whether every *_theory of the run is defined)
RUNS = (
    ("block", dict(t_end=0.2), None),                        # no closed form in its summary
    ("particle", dict(t_end=0.4), True),                     # departure from a sphere
    ("particle", dict(case="free", t_end=0.05), False),
    ("capstan", dict(), True),
    ("capstan", dict(bending_stiffness=1e-3, t_end=0.2), False),
    ("feeder", dict(t_end=0.2), True),
    ("feeder", dict(net_angle=45.0, t_end=0.1), False),
    ("fastening", dict(), True),
    ("fastening", dict(t_end=0.3), False),                   # the head never clamps: no tightening line
)

FORBIDDEN = ("_closed_form", "_expected", "closed_form_", "expected_", "theory_")


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


@pytest.fixture(scope="module")
def summaries():
    out = []
    with warnings.catch_warnings():      # the short runs' ledgers may not close to 1 %: not what is checked here
        warnings.simplefilter("ignore", EnergyWarning)
        for name, kw, defined in RUNS:
            model = MODELS[name]
            out.append((name, kw, defined, model.run(model.scene.Params(**kw)).summary))
    return out


def test_every_theory_sits_beside_its_value(summaries):
    for name, kw, defined, s in summaries:
        undefined = s["undefined"]
        theories = [k for k in s if k.endswith("_theory")]
        assert defined is None or theories, (name, kw, "no *_theory key")
        for k in theories:
            base = k[:-len("_theory")]
            assert base in s, (name, kw, f"{k} has no {base} beside it")
            v = s[k]
            if v is None:
                why = undefined.get(k)
                assert isinstance(why, str) and why.strip(), (name, kw, f"{k} is null without a reason")
            else:
                assert _is_number(v), (name, kw, k, v)
                assert k not in undefined, (name, kw, k)
        if defined is True:
            assert all(_is_number(s[k]) for k in theories), (name, kw, {k: undefined.get(k) for k in theories})
        elif defined is False:
            assert any(s[k] is None for k in theories), (name, kw)


def test_no_other_spelling_of_a_theory(summaries):
    for name, kw, _, s in summaries:
        for k in list(s) + list(s["undefined"]):
            assert not any(f in k for f in FORBIDDEN), (name, kw, k)
            assert "_theory" not in k or k.endswith("_theory"), (name, kw, k)
        for k in s["undefined"]:
            assert k in s, (name, kw, f"undefined names {k}, which is not in the summary")
