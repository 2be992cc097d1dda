#!/usr/bin/env bash
# The README's Speed section (issue 23): the in-betweening natively and in
# headless Chromium, tract against onnxruntime-web on every bundled model
# with tract's profile in wasm, and tract's native profile; all four outputs
# in one file, docs/speed_<date>.json, then the Markdown tables
# (scripts/speed_tables.py). Assumes scripts/setup.sh has run.
#
#   bash scripts/speed.sh [OUT.json]
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"
out=${1:-docs/speed_$(date +%F).json}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cargo bench -q --bench inbetween 2>/dev/null | sed -n '/^{/,$p' > "$tmp/native.json"
bash scripts/build-wasm.sh >/dev/null
node tests/web/bench_page.mjs > "$tmp/wasm.json"
node tests/web/bench_ort_page.mjs > "$tmp/ort.json"
cargo run -q --release --example profile_models 2>/dev/null > "$tmp/profile.json"
machine="$(nproc) cores, one thread per benchmark"
.venv/bin/python - "$tmp" "$out" "$machine" <<'EOF'
import json, os, sys, datetime
tmp, out, machine = sys.argv[1:]
d = {"date": datetime.date.today().isoformat(), "machine": machine}
for k in ("native", "wasm", "ort", "profile"):
    d[k] = json.load(open(os.path.join(tmp, f"{k}.json")))
json.dump(d, open(out, "w"), indent=1)
print(f"wrote {out}", file=sys.stderr)
EOF
.venv/bin/python scripts/speed_tables.py "$out"
