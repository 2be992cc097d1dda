#!/usr/bin/env bash
# Runs deeprep's libFuzzer targets (fuzz/fuzz_targets/) and prints one JSON
# object: per target, the executions, the crashes and the seconds taken.
#
#   bash scripts/fuzz.sh                    # every target, 10^4 executions each (the CI smoke)
#   bash scripts/fuzz.sh --runs 1000000     # 10^6 each
#   bash scripts/fuzz.sh --seconds 600 bvh_roundtrip
#
# Built with stable rustc and plain cargo: the flags below are the
# sanitizer-coverage instrumentation cargo-fuzz adds (no AddressSanitizer;
# Rust's own checks, debug assertions and overflow checks catch the bugs
# these targets look for). Each target starts from its committed corpus in
# tests/corpus/<kind>/ (the same files `cargo test --test hostile` reads)
# plus what earlier runs found (fuzz/corpus/, not committed); crashes are
# written to fuzz/artifacts/<target>/ and make this script exit 1.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$HOME/.cargo/bin:$PATH"

runs=10000
seconds=0
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(bvh_roundtrip bvh_motion gltf_rig keys_json hair_photo tween_manifest request mesh_obj hair_ppm cli_args)

declare -A SEEDS=([bvh_roundtrip]=bvh [bvh_motion]=bvh [gltf_rig]=gltf [keys_json]=keys [hair_photo]=hair
                  [tween_manifest]=manifest [request]=request [mesh_obj]=obj [hair_ppm]=ppm [cli_args]=args)
declare -A DICTS=([bvh_roundtrip]=fuzz/bvh.dict [bvh_motion]=fuzz/bvh.dict)

export CARGO_TARGET_DIR="${DEEPREP_FUZZ_TARGET_DIR:-$PWD/fuzz/target}"
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
 -Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
 -Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions -Coverflow-checks"
# An explicit --target keeps RUSTFLAGS off build scripts and proc macros
# (as cargo-fuzz does), which cannot link the coverage hooks.
host=$(rustc -vV | sed -n 's/^host: //p')
bins=()
for t in "${targets[@]}"; do bins+=(--bin "$t"); done
(cd fuzz && cargo build --release --target "$host" "${bins[@]}" 1>&2)

status=0
rows=()
for t in "${targets[@]}"; do
  work="fuzz/corpus/$t"
  art="fuzz/artifacts/$t/"
  mkdir -p "$work" "$art"
  log=$(mktemp)
  args=(-artifact_prefix="$art" -print_final_stats=1 -rss_limit_mb=2048 -timeout=10 -max_len=65536)
  if [ "$seconds" != 0 ]; then args+=(-max_total_time="$seconds"); else args+=(-runs="$runs"); fi
  [ -n "${DICTS[$t]:-}" ] && args+=(-dict="${DICTS[$t]}")
  t0=$(date +%s.%N)
  set +e
  "$CARGO_TARGET_DIR/$host/release/$t" "${args[@]}" "$work" "tests/corpus/${SEEDS[$t]}" >"$log" 2>&1
  rc=$?
  set -e
  t1=$(date +%s.%N)
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1)
  crashes=$(find "$art" -type f \( -name "crash-*" -o -name "oom-*" -o -name "timeout-*" -o -name "leak-*" \) | wc -l)
  if [ "$rc" != 0 ] || [ "$crashes" != 0 ]; then
    status=1
    echo "== $t failed (exit $rc); the end of its log:" >&2
    tail -30 "$log" >&2
  fi
  rows+=("$(printf '{"target":"%s","executions":%s,"crashes":%s,"exit":%s,"seconds":%.1f}' \
    "$t" "${execs:-0}" "$crashes" "$rc" "$(awk "BEGIN{print $t1 - $t0}")")")
  rm -f "$log"
done
printf '{"date":"%s","runs_per_target":%s,"seconds_per_target":%s,"targets":[%s]}\n' \
  "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "$runs" "$seconds" "$(IFS=,; echo "${rows[*]}")"
exit $status
