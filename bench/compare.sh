#!/usr/bin/env bash
# Compare `mpm bench` throughput of several builds on a noisy shared machine: runs them alternately, ROUNDS
# times each, and prints the median particle-steps/s of each and its ratio to the first.
# Usage: bench/compare.sh [-r ROUNDS] MPM_BINARY... -- [mpm bench options]
set -euo pipefail
rounds=5
if [ "${1:-}" = "-r" ]; then rounds=$2; shift 2; fi
bins=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do bins+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
declare -A results
for ((r = 0; r < rounds; ++r)); do
  for b in "${bins[@]}"; do
    v=$("$b" bench --json --repeat 1 "$@" | python3 -c 'import json,sys; print(json.load(sys.stdin)["particle_steps_per_second"])')
    results[$b]+="$v "
  done
done
base=""
for b in "${bins[@]}"; do
  med=$(echo "${results[$b]}" | tr ' ' '\n' | sed '/^$/d' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
  [ -z "$base" ] && base=$med
  python3 -c "print(f'{\"$b\"}: median {$med/1e6:.2f} M particle-steps/s over $rounds runs, ratio {$med/$base:.3f}')"
done
