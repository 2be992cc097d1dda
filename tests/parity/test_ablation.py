"""The data ablation table (train/deeprep_train/motion/ablation.py): ratios
to SLERP+LERP per gap from `residual eval --json` files, and the control
snapshots' range. No torch needed."""

import json

import pytest


def _eval(path, l2p, npss, speed):
    gaps = {str(g): {"slerp": {"l2p": 2.0, "npss": 4.0}, "model": {"l2p": a, "npss": b, "speed_ratio": c}}
            for g, a, b, c in zip((30, 120), l2p, npss, speed)}
    path.write_text(json.dumps({"split": "val", "ckpt": str(path), "gaps": gaps}))
    return str(path)


def test_rows_are_ratios_and_the_spread_covers_the_control_snapshots(train_import, tmp_path, monkeypatch, capsys):
    a = train_import("deeprep_train.motion.ablation")
    c = _eval(tmp_path / "c.json", (1.0, 1.5), (2.0, 3.0), (0.8, 0.7))
    b = _eval(tmp_path / "b.json", (1.2, 1.4), (2.0, 2.0), (0.9, 0.9))
    s = _eval(tmp_path / "s.json", (0.9, 1.6), (2.2, 3.2), (0.7, 0.8))
    out = tmp_path / "t.json"
    monkeypatch.setattr("sys.argv", ["ablation", f"control={c}", f"branch={b}", "--spread", c, s, "--json", str(out)])
    a.main()
    printed = capsys.readouterr().out
    assert "| control | 0.500 / 0.750 | 0.500 / 0.750 | 0.80 / 0.70 |" in printed
    assert "| branch | 0.600 / 0.700 | 0.500 / 0.500 | 0.90 / 0.90 |" in printed
    r = json.loads(out.read_text())
    assert r["gaps"] == [30, 120]
    assert r["control_spread"]["l2p"] == [[0.45, 0.5], [0.75, 0.8]]
    assert r["control_spread"]["speed"] == [[0.7, 0.8], [0.7, 0.8]]


def test_rows_with_other_gaps_than_the_control_are_refused(train_import, tmp_path, monkeypatch):
    a = train_import("deeprep_train.motion.ablation")
    c = _eval(tmp_path / "c.json", (1.0, 1.5), (2.0, 3.0), (0.8, 0.7))
    other = tmp_path / "o.json"
    other.write_text(json.dumps({"gaps": {"60": {"slerp": {"l2p": 1, "npss": 1},
                                                 "model": {"l2p": 1, "npss": 1, "speed_ratio": 1}}}}))
    monkeypatch.setattr("sys.argv", ["ablation", f"control={c}", f"x={other}"])
    with pytest.raises(SystemExit):
        a.main()
