#!/bin/bash
# Every accelerator against Embree on rays not made by the renderer: the adversarial families of
# adversarial_rays.py, rays aimed at the scene's own vertices, edges and planes (probe_rays), and
# shadow and diffuse workloads, closest hit and any hit, judged with `rayscout compare-hits --rays
# --scene` (world-space distance tolerance; a contact float arithmetic cannot decide, judged from
# its triangle, is excused; for any hit, --hits-a/--hits-b excuse a disagreement whose blocker is
# such a contact).
# usage: bench/audit/audit_vs_embree.sh BUILD_DIR SCENE.json OUT_DIR [N]
# prints one line per (ray set, query, accelerator) and the disagreements in full.
# ACCELS="bvh shafts@select=camera-voxels" audits these instead of every accelerator
# (name@key=value,key=value: with those --accel-opt tunables).
set -u
[ $# -ge 3 ] && [ $# -le 4 ] || { echo "usage: $0 BUILD_DIR SCENE.json OUT_DIR [N]" >&2; exit 2; }
build=$1 scene=$2 out=$3 n=${4:-40000}
R=$build/rayscout
[ -x "$R" ] || { echo "audit: $R: no rayscout binary (build the rayscout target in $build)" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
read -r lo hi < <($R info --scene "$scene" | awk '/^bounds:/ {gsub(/[(),]/, " "); print $3","$4","$5, $7","$8","$9}')
[ -n "${lo:-}" ] || { echo "audit: no bounds for $scene (see the error above)" >&2; exit 2; }
/usr/bin/python3 "$here/adversarial_rays.py" "$out" "$lo" "$hi" "$n" || exit 1
P=$build/bench/audit/probe_rays
[ -x "$P" ] || { echo "audit: $P: no probe_rays binary (build the probe_rays target in $build)" >&2; exit 2; }
$P "$scene" "$out" "$n" >/dev/null || exit 1
for w in shadow diffuse; do
  $R rays --scene "$scene" --workload $w --width 256 --height 192 --out "$out/W_$w.rays" >/dev/null || exit 1
done
status=0
for rays in "$out"/*.rays; do
  set_name=$(basename "$rays" .rays)
  for query in closest occluded; do
    ext=hits flag=
    [ $query = occluded ] && ext=occl flag=--occluded
    $R trace --scene "$scene" --rays "$rays" --accel embree --repeat 1 $flag --out "$out/$set_name.embree.$ext" >/dev/null || exit 1
    for accel in ${ACCELS:-$($R accelerators | awk '$1 != "brute" && $1 != "embree" {print $1}')}; do
      name=${accel%%@*} tunables=()
      [ "$name" != "$accel" ] && for kv in $(tr , " " <<< "${accel#*@}"); do tunables+=(--accel-opt "$kv"); done
      $R trace --scene "$scene" --rays "$rays" --accel "$name" "${tunables[@]}" --repeat 1 $flag --out "$out/$set_name.$accel.$ext" >/dev/null || exit 1
      # Any hit: a disagreement whose blocker is a grazing closest hit (traced just before) is excused.
      # In-plane and surface rays are grazing by construction, so their share of excused contacts
      # may be larger than the default 1 %.
      opts="--rays $rays --scene $scene"
      case $set_name in K_*|L_*) opts="$opts --max-grazing 0.25" ;; esac
      [ $ext = occl ] && opts="$opts --hits-a $out/$set_name.embree.hits --hits-b $out/$set_name.$accel.hits"
      if result=$($R compare-hits "$out/$set_name.embree.$ext" "$out/$set_name.$accel.$ext" $opts 2>&1); then
        grazing=$(sed -n 's/^grazing contacts: *\([0-9]*\).*/\1/p' <<< "$result")
        echo "$set_name $query $accel: OK${grazing:+ ($grazing grazing)}"
      else
        status=1
        echo "$set_name $query $accel: DIFFERENT"; echo "$result" | sed 's/^/    /'
      fi
    done
  done
done
exit $status
