"""docs/results.md's table for issue 20's partial keys and long gaps, from two
motion/eval.py runs on the validation takes:

  train/.venv/bin/python -m deeprep_train.motion.eval --gaps 60,120,300 \\
      --methods slerp,model,keys-root,keys-xy,cond-root,cond-xy --json docs/inbetween_control.json
  train/.venv/bin/python -m deeprep_train.motion.eval --gaps 1500 \\
      --methods slerp,model,residual-1,cond-pose,cond-root --json docs/inbetween_gap1500.json
  train/.venv/bin/python -m deeprep_train.motion.control_table

Replaces the block between <!-- control --> and <!-- /control --> in docs/results.md.
"""
import json
import os
import re

from deeprep_train.paths import ROOT  # noqa: E402
NAMES = {
    "slerp": "SLERP+LERP, whole-pose keys",
    "model": "networks, whole-pose keys",
    "keys-root": "networks, root-only keys",
    "keys-xy": "networks, 2-D keys (x, y of every joint + root)",
    "cond-root": "conditional network (`--method cond`), root-only keys",
    "cond-xy": "conditional network (`--method cond`), 2-D keys",
    "cond-pose": "conditional network (`--method cond`), whole-pose keys",
    "residual-1": "residual network, whole-pose keys",
}


def rows(res, methods, gaps):
    out = []
    for m in methods:
        cell = lambda k, f: " / ".join(f.format(res[f"{m}@{g}"][k]) for g in gaps)  # noqa: E731
        after = res[f"{m}@{gaps[0]}"].get("key_error_after_post")
        # methods that report no post-processing (SLERP+LERP, the residual
        # network, which the model method runs for whole-pose keys) are exact
        # by construction: MPJPE at the keys says so
        keys = f"{after[0]:.2f} / {after[1]:.2f}" if after else \
            "exact" if res[f"{m}@{gaps[0]}"]["MPJPE_at_keys"] < 1e-3 else ""
        out.append(f"| {NAMES[m]} | {cell('MPJPE', '{:.1f}')} | {cell('MPJPE_at_keys', '{:.1f}')} | "
                   f"{cell('NPSS', '{:.2f}')} | {cell('foot_skate', '{:.2f}')} | {cell('speed_ratio', '{:.2f}')} | {keys} |")
    return out


def main():
    ctl = json.load(open(os.path.join(ROOT, "docs", "inbetween_control.json")))
    long = json.load(open(os.path.join(ROOT, "docs", "inbetween_gap1500.json")))
    gaps = sorted({v["gap"] for v in ctl.values() if isinstance(v, dict)})
    head = ("| keys (validation takes) | MPJPE between keys | MPJPE at keys (root-relative) | NPSS | "
            "foot skating | joint speed / truth's | key error after post (root / joints) |\n|---|---|---|---|---|---|---|")
    windows = ctl[f"slerp@{gaps[0]}"]["windows"]
    text = "\n".join([
        "<!-- control -->",
        f"Partial keys (issue 20), keys every {' / '.join(map(str, gaps))} frames on the validation takes "
        f"({windows} windows at gap {gaps[0]}), the keys taken from the clip as "
        "`deeprep inbetween --from-bvh CLIP --keys ... --key-kind pose|root|xy` does (docs/inbetween_control.json; "
        "units are the data's, about cm; foot skating in units/frame, the truth's "
        f"{ctl['ground_truth_foot_skate']:.2f}):",
        "",
        head,
        *rows(ctl, [m for m in NAMES if f"{m}@{gaps[0]}" in ctl], gaps),
        "",
        f"A 1,500-frame gap (keys 1,500 frames apart, {long[f'slerp@1500']['windows']} windows: the validation "
        "clips long enough; hierarchically, Sec. 5.4.3: the generator over 600 frames, the conditional network over 300, "
        "and for whole-pose keys the networks row is the conditional network's when its manifest says default_for_long_gaps; "
        "docs/inbetween_gap1500.json):",
        "",
        head,
        *rows(long, [m for m in NAMES if f"{m}@1500" in long], [1500]),
        "<!-- /control -->",
    ])
    p = os.path.join(ROOT, "docs", "results.md")
    s = open(p).read()
    s = re.sub(r"<!-- control -->.*?<!-- /control -->", lambda _: text, s, flags=re.S)
    open(p, "w").write(s)
    print(text)


if __name__ == "__main__":
    main()
