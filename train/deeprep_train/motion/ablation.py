"""Issue 19, item 1: the data ablation table from `residual eval --json`
results of branches trained from one state, each with one data step changed.

    python -m deeprep_train.motion.ablation \\
        control=cache/abl_control/val_121000.json \\
        "D.2 filter=cache/abl_d2/val_121000.json" ... \\
        --spread cache/abl_control/val_119000.json ... \\
        --json ../docs/inbetween_ablation.json

The first row is the control. `--spread` takes the control's snapshots
(its own among them, or not): the range their numbers cover is what a
branch's number moves by with no change at all, so a difference inside it
is not an effect.
Prints a markdown table (ratios to SLERP+LERP on the same windows, below 1
is better; joint speed as a share of the truth's) and writes every number
to --json.
"""
import argparse
import json

METRICS = ("l2p", "npss", "speed")


def ratio_to_slerp(g, metric):
    """The model's `metric` over SLERP+LERP's on the same windows, per gap in
    increasing order, from the "gaps" of one `residual eval --json` file
    (gaps whose model lacks the metric are left out). The one place this
    ratio is taken: the ablation table and `residual pick` both use it."""
    return [g[k]["model"][metric] / g[k]["slerp"][metric] for k in sorted(g, key=int) if metric in g[k]["model"]]


def scores(path):
    """{metric: [value per gap]} and the gaps of one `residual eval --json`
    file: L2P and NPSS as ratios to SLERP+LERP's, joint speed as given."""
    r = json.load(open(path))
    g = r["gaps"]
    gaps = sorted(g, key=int)
    out = {"l2p": ratio_to_slerp(g, "l2p"), "npss": ratio_to_slerp(g, "npss"),
           "speed": [g[k]["model"]["speed_ratio"] for k in gaps]}
    return gaps, out, r.get("split"), r.get("ckpt")


def table(rows, spread):
    """Markdown lines for labelled rows [(label, scores)] and the spread
    {metric: [(lo, hi) per gap]} of the control's snapshots (or None)."""
    fmt = lambda v, d: " / ".join(f"{x:.{d}f}" for x in v)  # noqa: E731
    lines = ["| data | L2P ratio | NPSS ratio | joint speed |", "|---|---|---|---|"]
    for label, s in rows:
        lines.append(f"| {label} | {fmt(s['l2p'], 3)} | {fmt(s['npss'], 3)} | {fmt(s['speed'], 2)} |")
    if spread:
        cell = lambda m, d: " / ".join(f"{lo:.{d}f}-{hi:.{d}f}" for lo, hi in spread[m])  # noqa: E731
        lines.append(f"| the control's snapshots (range) | {cell('l2p', 3)} | {cell('npss', 3)} "
                     f"| {cell('speed', 2)} |")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("rows", nargs="+", help="LABEL=EVAL_JSON, the control first")
    ap.add_argument("--spread", nargs="*", default=[], help="the control's snapshots' eval JSON files")
    ap.add_argument("--json")
    args = ap.parse_args()
    rows, meta, gaps = [], [], None
    for item in args.rows:
        if "=" not in item:
            ap.error(f"'{item}' is not LABEL=EVAL_JSON")
        label, path = item.split("=", 1)
        g, s, split, ckpt = scores(path)
        if gaps is not None and g != gaps:
            ap.error(f"{path} has gaps {g}, the control {gaps}")
        gaps = g
        rows.append((label, s))
        meta.append({"label": label, "eval": path, "split": split, "ckpt": ckpt, **s})
    spread = None
    if args.spread:
        snaps = [scores(p)[1] for p in args.spread]
        spread = {m: [(min(s[m][i] for s in snaps), max(s[m][i] for s in snaps)) for i in range(len(gaps))]
                  for m in METRICS}
    print(f"gaps {' / '.join(gaps)}")
    print("\n".join(table(rows, spread)))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"gaps": [int(g) for g in gaps], "rows": meta, "control_spread_files": args.spread,
                       "control_spread": spread}, fh, indent=1)


if __name__ == "__main__":
    main()
