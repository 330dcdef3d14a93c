#!/usr/bin/env bash
# The main job: smooth a noisy benchmark mesh (default: Fandisk0.3) with our plugin through the
# real meshlabserver, at its defaults (the automatic mode) and in its ring-barycentre (the paper's
# patch), feature-preserving and organic modes, next to MeshLab's own Laplacian Smooth x5, and
# print θ, Ev and volume ratio against the clean mesh.
#
# It says what it does at each stage and shows the build's own progress. It installs and builds
# only what it needs: Debian's packages and MeshLab's sources (scripts/setup.sh), the plugin and
# the two tools it calls (write_mlx, mesh_compare); the test suite builds the rest.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
build="${SBS_BUILD_DIR:-$top/build}"
case_dir="${1:-$top/../shared/data/benchmark/Fandisk0.3}"
start=$SECONDS
stage() { printf '\n== [%3ds] %s\n' $((SECONDS - start)) "$*"; }

stage "installing what is missing (Debian's meshlab, Qt5, Eigen; MeshLab's sources for the headers)"
bash "$top/scripts/setup.sh"
stage "configuring the build in $build"
cmake -S "$top" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
stage "building the plugin and the tools it needs (the build's own progress follows)"
cmake --build "$build" -j"$(nproc)" --target filter_saliency_bezier_smooth write_mlx mesh_compare

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/meshlab
"$build/tools/write_mlx" smooth >"$out/ours.mlx"
"$build/tools/write_mlx" smooth placement=ring >"$out/ring.mlx"
"$build/tools/write_mlx" smooth placement=feature >"$out/feature.mlx"
"$build/tools/write_mlx" smooth placement=organic >"$out/organic.mlx"
cat >"$out/laplacian.mlx" <<'MLX'
<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Laplacian Smooth">
  <Param name="stepSmoothNum" type="RichInt" value="5"/>
  <Param name="Boundary" type="RichBool" value="true"/>
  <Param name="cotangentWeight" type="RichBool" value="true"/>
  <Param name="Selected" type="RichBool" value="false"/>
 </filter>
</FilterScript>
MLX
stage "smoothing $(basename "$case_dir")/noisy.ply through meshlabserver $(dpkg-query -W -f='${Version}' meshlab)"
for run in ours ring feature organic laplacian; do
  printf '   %-10s ' "$run"
  t0=$SECONDS
  xvfb-run -a "$build/meshlab/meshlabserver" -i "$case_dir/noisy.ply" -o "$out/$run.ply" \
    -s "$out/$run.mlx" >"$out/$run.log" 2>&1 || true
  [ -f "$out/$run.ply" ] || { echo "meshlabserver failed:"; cat "$out/$run.log"; exit 1; }
  echo "done in $((SECONDS - t0)) s"
done

stage "scoring against $(basename "$case_dir")/clean.ply (tools/mesh_compare)"
score() { "$build/tools/mesh_compare" "$1" "$case_dir/clean.ply" 2>/dev/null | python3 -c "
import json, sys
r = json.load(sys.stdin)
print('theta %6.2f deg   Ev %5.2f e-3   volume ratio %.4f   flipped faces %d'
      % (r['theta_deg'], r['ev_1e3'], r['volume_ratio'], r['flipped_faces']))"; }
printf '  %-28s' "noisy input:"; score "$case_dir/noisy.ply"
printf '  %-28s' "Saliency Bezier Smooth:"; score "$out/ours.ply"
printf '  %-28s' " ... ring barycentre:"; score "$out/ring.ply"
printf '  %-28s' " ... feature-preserving:"; score "$out/feature.ply"
printf '  %-28s' " ... organic scan:"; score "$out/organic.ply"
printf '  %-28s' "MeshLab Laplacian Smooth x5:"; score "$out/laplacian.ply"
# meshlabserver echoes the filter's log as "LOG: <level> <line>" (the plain copy may share a line
# with the progress messages).
grep -E "^LOG: [0-9]+ (Automatic|Volume|Time)" "$out/ours.log" | sed -E 's/^LOG: [0-9]+ /  log: /'
echo "(whole demo: $((SECONDS - start)) s)"
