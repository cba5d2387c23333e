#!/usr/bin/env bash
# Build the libFuzzer targets (clang, ASan + UBSan), replay every input that ever crashed them
# (fuzz/regressions/TARGET/), then fuzz each target for SECONDS (default 60) from a seed corpus: the example
# scenes, and checkpoints written by build/bin/mpm from them; then the Python scene conversion for SECONDS. Fails on
# any crash, leak, hang or uncaught exception; the input that caused it is left in build-fuzz/artifacts/ (add it
# to fuzz/regressions/ once fixed).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMPM_BUILD_FUZZERS=ON \
  -DMPM_BUILD_TESTS=OFF "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_scene fuzz_checkpoint

corpus=build-fuzz/corpus
artifacts=build-fuzz/artifacts/
rm -rf "$corpus" "$artifacts" && mkdir -p "$corpus/fuzz_scene" "$corpus/fuzz_checkpoint" "$artifacts"
for scene in examples/*/scene.toml examples/implicit/*.toml examples/contact/*.toml; do
  name=$(echo "$scene" | tr '/' '_')
  cp "$scene" "$corpus/fuzz_scene/$name"
  # A checkpoint of the first step (27-390 kB).
  if [ -x build/bin/mpm ] && build/bin/mpm run "$scene" --out "build-fuzz/seed-$name" --stop-after 1 --quiet \
       >/dev/null 2>&1; then
    cp "build-fuzz/seed-$name/checkpoint.h5" "$corpus/fuzz_checkpoint/$name.h5"
  fi
done

# Checkpoints are sealed (src/io/checkpoint_seal.hpp): HDF5 reads only files exactly as written, so both targets
# run with leak detection, a 2 GB RSS limit and ASan's default of failing oversized allocations.
declare -A max_len=([fuzz_scene]=8192 [fuzz_checkpoint]=400000)
for target in fuzz_scene fuzz_checkpoint; do
  mapfile -t inputs < <(find "fuzz/regressions/$target" -type f ! -name .keep)
  if [ ${#inputs[@]} -gt 0 ]; then
    echo "== $target: replaying ${#inputs[@]} input(s) of fuzz/regressions/$target"
    ASAN_OPTIONS=halt_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
      "build-fuzz/bin/$target" "${inputs[@]}" 2>&1 | tail -1
  fi
  dict=()
  [ -f "fuzz/$target.dict" ] && dict=(-dict="fuzz/$target.dict")
  echo "== $target: fuzzing for $seconds s"
  ASAN_OPTIONS=halt_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "build-fuzz/bin/$target" "$corpus/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len="${max_len[$target]}" -artifact_prefix="$artifacts" -print_final_stats=1 "${dict[@]}" 2>&1 |
    grep -E "stat::number_of_executed_units|stat::new_units_added|ERROR|SUMMARY|artifact|Done" || true
  if [ -n "$(ls -A "$artifacts")" ]; then
    echo "fuzz: $target found a failing input: $(ls "$artifacts")" >&2
    exit 1
  fi
done

# The Python scene conversion (mpm.Scene.from_dict), which libFuzzer cannot drive: a mutation fuzzer of its own on
# the release build's module, for the same time (python/tests/scene_dict_fuzz.py).
if [ -f build/python/mpm/__init__.py ] && [ -f build/python/interpreter ]; then
  echo "== scene_dict_fuzz: fuzzing for $seconds s"
  PYTHONPATH=build/python "$(cat build/python/interpreter)" python/tests/scene_dict_fuzz.py "$seconds"
fi
