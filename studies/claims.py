"""The speed figures the documentation quotes, against their result files and rerun.

    python studies/claims.py [--rerun] [--quick] [--out DIR]

Each claim is a figure a page of docs/ quotes as "median [min-max]" (the speed targets and the
command line's cost on docs/guide/speed.md, the Newton settings on docs/guide/settings.md) with the
row of a committed result file it comes from (the file names the command that makes it). Without ``--rerun`` this
checks that every page quotes its file as it stands (the text is on the page); with ``--rerun`` it
also runs each claim's study afresh (``python studies/STUDY.py --out DIR/STUDY``, ``--quick`` for
the short form, whose figures are not comparable) and prints the new median beside the quoted one
with whether it lands inside the quoted spread. Speed figures move with the machine's load (up to
about 10 % on a ratio from hour to hour on the 2-core machine of the figures), so a rerun can land
outside the spread of a quiet hour; the spread says how far one run of the command scatters.
Writes ``claims.csv`` and ``report.md`` with ``--rerun`` (default ``studies/results/claims``).
"""
from __future__ import annotations

import argparse
import csv
import os
import subprocess
import sys
from dataclasses import dataclass

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


@dataclass(frozen=True)
class Claim:
    """A quoted figure: the page, the study and its result file, the row (key column, value; more
    pairs in ``also``), the figure's column (its _min and _max beside it), how the page prints it
    and the factor from the file's unit to the page's."""
    page: str
    study: str
    file: str
    key: str
    row: str
    column: str
    fmt: str = "{:.2f}"
    also: tuple = ()
    scale: float = 1.0


SPEED = "docs/guide/speed.md"
_TARGET_ROWS = ["full block, 4 corners", "full block, 8 x 8 grid", "64 cubes, one contact set each",
                "64 cubes, one group", "64 cubes, one group, undamped (the corners chatter)",
                "one contact set each: per body, 64 / 8 cubes", "one group: per body, 64 / 8 cubes",
                "reduced screw (default ScrewParams)", "moving master (full block, 4 corners, on a free plate)",
                "the moving master's plate alone: the fixed-plane block with the free plate beside it",
                "moving master against the same two bodies with the contact on the fixed plane",
                "user's 4-point body in a spherical bowl (Sphere)", "user's 4-point body down a conical trough (Cone)"]
CLAIMS = ([Claim(SPEED, "benchmarks", "targets.csv", "scene [-]", r, "ratio [-]") for r in _TARGET_ROWS]
          + [Claim(SPEED, "benchmarks", "targets.csv", "scene [-]",
                   "compiled call on the plane, as Exudyn makes it: " + part, "ours [us]", "{:.3f}")
             for part in ("fixed part [us]", "per point [us]")]
          + [Claim(SPEED, "cli_cost", "cli_cost.csv", "overrides [-]", r, c, f)
             for r in ("model=full points=corners", "model=full points=grid:8", "defaults")
             for c, f in (("total [us]", "{:.1f}"), ("ratio [-]", "{:.2f}"))]
          # the solver settings' table: us per step of each scene at each of five Newton settings
          + [Claim("docs/guide/settings.md", "newton_settings", "newton_settings.csv", "settings [-]", setting,
                   "cpu_per_step [s]", "{:.1f}", (("scene [-]", scene), ("model [-]", model), ("points [-]", points)),
                   1e6)
             for scene, model, points in (("block", "planar", "corners"), ("block", "full", "corners"),
                                          ("block", "full", "grid:8"), ("screw", "reduced", "3 x 8"),
                                          ("screw", "full", "3 x 8"))
             for setting in ("full_newton_1e-10", "package", "package_1e-8", "exudyn", "jacobian_per_step")])


def _read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def figure(rows, claim):
    """(median, min, max) of the claim's row in the rows of its file."""
    for r in rows:
        if r[claim.key] == claim.row and all(r[k] == v for k, v in claim.also):
            base, unit = claim.column.rsplit(" ", 1)
            return tuple(claim.scale * float(r[f"{base}{s} {unit}"]) for s in ("", "_min", "_max"))
    raise KeyError(f"{claim.file}: no row {claim.key} = {claim.row!r} {dict(claim.also)}")


def quoted_text(claim, values):
    med, lo, hi = (claim.fmt.format(v) for v in values)
    return f"{med} [{lo}-{hi}]"


def check_pages(results=os.path.join(ROOT, "docs", "results")):
    """[(claim, quoted (median, min, max), the text, found on the page)] for every claim."""
    out, pages, files = [], {}, {}
    for c in CLAIMS:
        page = pages.setdefault(c.page, open(os.path.join(ROOT, c.page)).read())
        rows = files.setdefault((c.study, c.file), _read(os.path.join(results, c.study, c.file)))
        values = figure(rows, c)
        text = quoted_text(c, values)
        out.append((c, values, text, text in page))
    return out


def rerun(out_dir, quick):
    """Run each claim's study once into out_dir/STUDY; {study: its output folder}."""
    done = {}
    for study in dict.fromkeys(c.study for c in CLAIMS):
        folder = os.path.join(out_dir, study)
        cmd = [sys.executable, os.path.join(HERE, f"{study}.py"), "--out", folder] + (["--quick"] if quick else [])
        print("claims: " + " ".join(cmd), flush=True)
        subprocess.run(cmd, check=True)
        done[study] = folder
    return done


def main(argv=None):
    ap = argparse.ArgumentParser(prog="studies/claims.py", description=__doc__.splitlines()[0])
    ap.add_argument("--rerun", action="store_true", help="run the studies afresh and compare")
    ap.add_argument("--quick", action="store_true", help="with --rerun: the studies' short forms (not comparable)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "claims"))
    a = ap.parse_args(argv)
    checked = check_pages()
    missing = [(c, text) for c, _, text, found in checked if not found]
    for c, text in missing:
        print(f"claims: {c.page} does not quote {c.file} {c.row!r} {c.column} as it stands: {text}", file=sys.stderr)
    if not a.rerun:
        print(f"claims: {len(checked) - len(missing)} of {len(checked)} quoted figures are their result files' "
              "(rerun them with --rerun)")
        return 1 if missing else 0
    folders = rerun(a.out, a.quick)
    head = ["page", "file", "row", "column", "quoted median [min-max]", "rerun", "inside the spread"]
    lines = []
    for c, values, text, _ in checked:
        new = figure(_read(os.path.join(folders[c.study], c.file)), c)[0]
        inside = values[1] <= new <= values[2]
        lines.append([c.page, c.file, c.row, c.column, text, c.fmt.format(new), "yes" if inside else "no"])
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "claims.csv"), "w", newline="") as f:
        csv.writer(f).writerows([head] + lines)
    report = "| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n" + "\n".join(
        "| " + " | ".join(r) + " |" for r in lines)
    with open(os.path.join(a.out, "report.md"), "w") as f:
        f.write("## The quoted speed figures, rerun\n\n`python studies/claims.py --rerun`"
                + (" --quick" if a.quick else "") + "\n\n" + report + "\n")
    print(report)
    return 1 if missing else 0


if __name__ == "__main__":
    raise SystemExit(main())
