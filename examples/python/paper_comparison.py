"""The paper's comparison from Python (Mahapatra & Ghosal, section 3): for each of the three
paper cases, the literal geometric method against the Cosserat rod driven by the paper's
cable tensions (the paper's own comparison, RMS over the disks next to the paper's figure),
and the whole-robot energy model against the rod driven by the same cable shortenings.
Draws three views per case with matplotlib (the layout of the paper's Fig. 3).

    python examples/python/paper_comparison.py [OUT_DIR]     # writes OUT_DIR/paper_comparison.png
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import ccrkit

ROOT = Path(__file__).resolve().parents[2]
#: RMS between the paper's two models, its section 3 [mm].
PAPER_RMS_MM = (1.57, 1.52, 1.19)

#: (label, method, settings, what drives it)
CURVES = (
    ("literal geometric", "geometric", {}, "shortenings"),
    ("energy", "energy", {}, "shortenings"),
    ("Cosserat rod", "cosserat", {"control": "displacement"}, "shortenings"),
    ("Cosserat rod", "cosserat", {"control": "force"}, "the paper's tensions"),
)


def rms_mm(a: ccrkit.Shape, b: ccrkit.Shape) -> float:
    """RMS distance between corresponding disk centres [mm]."""
    d = a.disk_positions - b.disk_positions
    return float(np.sqrt((d * d).sum(axis=1).mean()) * 1e3)


def solve_cases():
    """Every case's four shapes, keyed by (label, driven by)."""
    out = []
    for case in (1, 2, 3):
        model = ccrkit.Model.load(ROOT / "models" / "paper" / f"case{case}.toml")
        shapes = {(lbl, by): model.solve(m, **s) for lbl, m, s, by in CURVES}
        out.append((model, shapes))
    return out


def table(cases):
    """Rows of (case, literal-vs-rod(force) RMS, paper's RMS, energy-vs-rod(shortening) RMS) [mm]."""
    rows = []
    for i, (_, s) in enumerate(cases):
        lit = rms_mm(s[("literal geometric", "shortenings")], s[("Cosserat rod", "the paper's tensions")])
        en = rms_mm(s[("energy", "shortenings")], s[("Cosserat rod", "shortenings")])
        rows.append((i + 1, lit, PAPER_RMS_MM[i], en))
    return rows


def draw(cases, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    views = (("x", "z", 0, 2), ("y", "z", 1, 2), ("x", "y", 0, 1))
    styles = ("-", "--", ":", "-.")
    fig, axes = plt.subplots(len(cases), 3, figsize=(12, 4 * len(cases)))
    for r, (model, shapes) in enumerate(cases):
        for c, (h, v, i, j) in enumerate(views):
            ax = axes[r, c]
            for (key, shape), ls in zip(shapes.items(), styles):
                b = shape.backbone * 1e3
                ax.plot(b[:, i], b[:, j], ls, label=f"{key[0]} ({key[1]})")
                p = shape.disk_positions * 1e3
                ax.plot(p[:, i], p[:, j], "o", ms=2, color=ax.lines[-1].get_color())
            ax.set(xlabel=f"{h} [mm]", ylabel=f"{v} [mm]", title=f"{model.name}: {h}-{v} view")
            ax.set_aspect("equal", adjustable="datalim")
    axes[0, 0].legend(fontsize=7, loc="best")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def main(out_dir: Path) -> list:
    cases = solve_cases()
    rows = table(cases)
    print("| case | literal vs rod (tensions) RMS | paper's RMS | energy vs rod (same shortenings) RMS |")
    print("|---|---|---|---|")
    for case, lit, paper, en in rows:
        print(f"| {case} | {lit:.2f} mm | {paper:.2f} mm | {en:.3f} mm |")
    out = out_dir / "paper_comparison.png"
    draw(cases, out)
    print(f"wrote {out}")
    return rows


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "target")
