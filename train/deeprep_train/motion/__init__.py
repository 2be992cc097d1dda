"""Motion: keyframe in-betweening (thesis chapter 5) — data, networks,
training, evaluation and export. Run the entry points with
``python -m deeprep_train.motion.<module>`` (see train/README.md)."""
