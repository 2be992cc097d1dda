"""`python -m deeprep_train.motion.residual CMD`: the command line (see the package docstring)."""
import argparse
import os

from deeprep_train.paths import CACHE
from deeprep_train.motion.residual.data import OUT, PORTABLE, add_fill_args, prepare
from deeprep_train.motion.residual.net import DILATIONS
from deeprep_train.motion.residual.evaluation import evaluate, pick
from deeprep_train.motion.residual.training import train
from deeprep_train.motion.residual.export import export, portable, prune


def main():
    ap = argparse.ArgumentParser(prog="python -m deeprep_train.motion.residual")
    ap.add_argument("cmd", choices=["prepare", "train", "eval", "portable", "export", "pick", "prune"])
    ap.add_argument("results", nargs="*", help="pick: eval --json files of the candidates")
    ap.add_argument("--data", default=os.path.join(CACHE, "resid60.npz"))
    ap.add_argument("--out", default=OUT)
    ap.add_argument("--minutes", type=float, default=60)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--device", default="cpu", help="torch device for training (cuda on a lent GPU)")
    ap.add_argument("--to", help="portable: where to write (default train/checkpoints/tween_resid_w128b.pt)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--width", type=int, default=192)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--frames", type=int, default=480)
    ap.add_argument("--lr", type=float, default=5e-4)
    ap.add_argument("--ema", type=float, default=0.999)
    ap.add_argument("--mirror", type=int, default=1)
    ap.add_argument("--speed-weight", type=float, default=0.0)
    ap.add_argument("--foot-weight", type=float, default=0.0)
    ap.add_argument("--l2p-weight", type=float, default=0.0,
                    help="weight of the position loss in L2P's units (per-coordinate spread)")
    ap.add_argument("--spectral-weight", type=float, default=0.0,
                    help="weight of the short-time spectrum loss on root-relative positions (NPSS's view)")
    ap.add_argument("--dilations", type=lambda s: tuple(int(x) for x in s.split(",")), default=DILATIONS,
                    help="one residual block per dilation; resuming with more than saved appends identity blocks")
    ap.add_argument("--speed-margin", type=float, default=0.0,
                    help="pick: ask joint speed within 30%% minus this of the truth's at gaps 120 and 300 on training "
                         "takes (validation has come out lower: run G 0.81 -> 0.74 at 120, 0.76 -> 0.74 at 300)")
    ap.add_argument("--l2p-margin", type=float, default=0.0,
                    help="pick: ask L2P at most 1 minus this of SLERP+LERP's at every gap on training takes (the "
                         "stride-2 networks lost 0.08 of that ratio at gap 30 on validation)")
    ap.add_argument("--d2-filter", help="train: only the training frames motion/filter_d2.py keeps "
                                        "(its .npz, e.g. train/cache/d2_filter.npz)")
    ap.add_argument("--gan-weight", type=float, default=0.0,
                    help="the adversarial stage (residual_adv.py): weight of the network's LSGAN loss; 0 trains "
                         "with supervision only")
    ap.add_argument("--cross-clip", type=float, default=0.0,
                    help="cross-clip keys (Sec. 5.2.7 rule 2): probability scale p; an interval of g >= 180 frames "
                         "takes its end key from another clip with probability p * g / 300 (such windows get only "
                         "the adversarial loss)")
    ap.add_argument("--lr-d", type=float, default=1e-4, help="the discriminator's learning rate (Adam)")
    ap.add_argument("--d-warmup", type=int, default=300,
                    help="discriminator-only steps when the checkpoint has no discriminator")
    ap.add_argument("--regular-keys", type=float, default=0.0,
                    help="train: the share of windows whose keys are evenly spaced (one interval drawn and repeated; "
                         "the rest draw each interval)")
    ap.add_argument("--name", default="tween_residual",
                    help="export: the file's name (tween_fill_long: the long-gap filling network, with --fill-up-to)")
    add_fill_args(ap, "tween_fill_long")
    ap.add_argument("--gan-min-gap", type=int, default=0,
                    help="train: the adversarial loss's gradient skips frames of intervals shorter than this "
                         "(frames); the supervised terms alone train them (issue 19: the adversary cost L2P at gap 30)")
    ap.add_argument("--skip", action="store_true",
                    help="train: add a full-rate 1x1 skip from the input to the output convolution (zero at first; "
                         "for stride 2, issue 19's short gaps); a checkpoint with one keeps it")
    ap.add_argument("--stride", type=int, choices=[1, 2],
                    help="train: 2 runs the blocks at every second frame (half their arithmetic; issue 23); "
                         "default: the resumed checkpoint's, else 1")
    ap.add_argument("--recipe", help="export: how the checkpoint was trained, one sentence for the manifest and the "
                                     "README's models table (checkpoints do not record their training flags)")
    ap.add_argument("--teacher", help="train: a trained checkpoint whose moving average the network learns to "
                    "match (knowledge distillation, e.g. a wider network into a pruned one)")
    ap.add_argument("--distill-weight", type=float, default=0.0,
                    help="train: weight of the L1 distance to --teacher's output (positions, 6D rotations "
                    "and root, as the supervised terms measure them), on every window")
    ap.add_argument("--distill-speed-weight", type=float, default=0.0,
                    help="train: weight of the L1 distance of per-joint speeds (the supervised speed term) to "
                    "--teacher's, on every window")
    ap.add_argument("--resume", action="store_true")
    ap.add_argument("--portable", default=PORTABLE,
                    help="train --resume without a checkpoint in --out starts from this float16 file "
                         "(default train/checkpoints/tween_resid_w128b.pt, the running width-128 branch)")
    ap.add_argument("--save-every", type=int, default=250)
    ap.add_argument("--snapshot-every", type=int, default=1000)
    ap.add_argument("--split", default="train")
    ap.add_argument("--ckpt")
    ap.add_argument("--gaps", type=lambda s: [int(x) for x in s.split(",")], default=[30, 60, 120, 300])
    ap.add_argument("--json")
    args = ap.parse_args()
    if args.cmd == "prepare":
        prepare(args.data)
    elif args.cmd == "train":
        train(args)
    elif args.cmd == "portable":
        portable(args)
    elif args.cmd == "export":
        export(args)
    elif args.cmd == "pick":
        pick(args)
    elif args.cmd == "prune":
        prune(args)
    else:
        evaluate(args)


if __name__ == "__main__":
    main()
