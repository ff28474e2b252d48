#!/usr/bin/env bash
# Run every fuzz target for SECONDS (default 600), JOBS at a time (default 2), from its corpus,
# seeds and regression inputs, on the stable toolchain; print one Markdown table row a target:
# executions, executions a second, and the result (a crash stops the target and lands in
# artifacts/TARGET/). Logs: campaign/TARGET.log.
#
#   bash fuzz/campaign.sh 600 2
set -euo pipefail
cd "$(dirname "$0")"
seconds="${1:-600}"
jobs="${2:-2}"
export RUSTC_BOOTSTRAP=1
targets=(read_abc read_ct2hair read_data read_gltf read_hair read_obj read_satfdb read_scene read_tfx read_usd)
cargo fuzz build -O >/dev/null
mkdir -p campaign
run() {
  local t="$1"
  mkdir -p "corpus/$t" "seeds/$t" "regressions/$t"
  # -rss_limit_mb: an input that makes a reader allocate past 2 GB is a crash too.
  if cargo fuzz run -O "$t" "corpus/$t" "seeds/$t" "regressions/$t" -- \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 >"campaign/$t.log" 2>&1; then
    echo "ok" >"campaign/$t.result"
  else
    echo "CRASH (see campaign/$t.log, artifacts/$t/)" >"campaign/$t.result"
  fi
}
running=0
for t in "${targets[@]}"; do
  run "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n
    running=$((running - 1))
  fi
done
wait
echo "| target | executions | per second | result |"
echo "| --- | ---: | ---: | --- |"
for t in "${targets[@]}"; do
  # libFuzzer's last status line: "#N DONE ... exec/s: R ..." (or the last pulse before a crash).
  line=$(grep -a -E '^#[0-9]+' "campaign/$t.log" | tail -1)
  execs=$(sed -E 's/^#([0-9]+).*/\1/' <<<"$line")
  rate=$(sed -E 's/.*exec\/s: ([0-9]+).*/\1/' <<<"$line")
  echo "| \`$t\` | $execs | $rate | $(cat "campaign/$t.result") |"
done
