#!/usr/bin/env bash
# Profile a cold build (docs/build.md): configure BUILD_DIR (default build-profile) afresh with every compile
# wrapped in /usr/bin/time, build the program alone and then everything with JOBS jobs (default 2), and print the
# wall times, the ten heaviest units (seconds, peak resident memory) and how many units include a few headers.
# No ccache: the times are those of a machine that has never built the tree.
set -euo pipefail
cd "$(dirname "$0")/.."
dir="${1:-build-profile}"
jobs="${2:-2}"
rm -rf "$dir"
mkdir -p "$dir"
log="$PWD/$dir/units.log"
wrap="$PWD/$dir/time-unit.sh"
cat >"$wrap" <<EOF
#!/usr/bin/env bash
# seconds, peak resident kB and object of one compile
out=""; prev=""
for a in "\$@"; do [ "\$prev" = "-o" ] && out="\$a"; prev="\$a"; done
exec /usr/bin/time -f "%e %M \$out" -a -o "$log" "\$@"
EOF
chmod +x "$wrap"
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER_LAUNCHER="$wrap" >/dev/null
start=$(date +%s)
cmake --build "$dir" -j"$jobs" --target mpm >/dev/null
program=$(($(date +%s) - start))
cmake --build "$dir" -j"$jobs" >/dev/null
all=$(($(date +%s) - start))
echo "cold build with $jobs jobs: the program $program s, everything $all s"
awk '{s += $1; if ($2 > m) m = $2} END {printf "%d units, %.0f s of compiling, largest peak %.2f GB\n", NR, s, m / 1048576}' "$log"
echo "the ten heaviest units (s, peak GB, object):"
sort -rn "$log" | head -10 | awk '{printf "  %7.1f  %5.2f  %s\n", $1, $2 / 1048576, $3}'
echo "units that include (of all units with a dependency file):"
mapfile -t deps < <(find "$dir" -name '*.o.d')
for h in mpm/shape/stencil.hpp mpm/transfer/p2g.hpp Eigen/Dense Eigen/src/SVD/JacobiSVD.h mpm/explicit/spec.hpp; do
  printf '  %-32s %d of %d\n' "$h" "$(grep -l "$h" "${deps[@]}" | wc -l)" "${#deps[@]}"
done
