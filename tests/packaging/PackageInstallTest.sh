#!/usr/bin/env bash
# Builds the .deb with CPack, unpacks it into a scratch root (dpkg -x, no
# root needed) and runs the installed programs from there, without the
# source or build tree's data: the package must hold everything they need.
# Usage: PackageInstallTest.sh BUILD_DIR
set -euo pipefail
build_dir=$1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

if ! cpack --config "$build_dir/CPackConfig.cmake" -B "$scratch/pkg" > "$scratch/cpack.log" 2>&1; then
  cat "$scratch/cpack.log"
  fail "cpack did not make the package"
fi
deb=$(ls "$scratch"/pkg/*.deb)
echo "package: $(basename "$deb"), $(du -h "$deb" | cut -f1)"
info=$(dpkg-deb --info "$deb")
grep -q "^ Package: ambler-gs$" <<< "$info" || fail "package name"
# dpkg-shlibdeps found the libraries the programs link.
for lib in libqt6widgets6 libvtk9 libpcl-io libopencv-imgproc libddsc; do
  grep -q "^ Depends:.*$lib" <<< "$info" || fail "Depends does not name $lib"
done

root=$scratch/root
dpkg -x "$deb" "$root"
for f in usr/bin/ambler-gs usr/bin/ambler-cli usr/bin/ambler-sim \
         usr/share/applications/ambler-gs.desktop \
         usr/share/icons/hicolor/scalable/apps/ambler-gs.svg \
         usr/share/ambler/config/rover.json usr/share/ambler/config/scanner.json \
         usr/share/ambler/samples/README.md usr/share/ambler/samples/scan-seed1/scan.tif \
         usr/share/ambler/samples/striper-seed3/striper.json \
         usr/share/ambler/samples/camera-seed1/image.tif \
         usr/share/doc/ambler-gs/README.md usr/share/doc/ambler-gs/docs/user-guide.md; do
  [[ -e $root/$f ]] || fail "the package lacks /$f"
done
grep -q "^Exec=ambler-gs$" "$root/usr/share/applications/ambler-gs.desktop" || fail "desktop Exec"
if command -v desktop-file-validate > /dev/null; then
  desktop-file-validate "$root/usr/share/applications/ambler-gs.desktop"
fi

cli=$root/usr/bin/ambler-cli
version=$(env -u AMBLER_DATA_DIR "$cli" --version)
echo "$version"
grep -q "^ambler-cli [0-9]\+\.[0-9]\+\.[0-9]\+$" <<< "$version" || fail "ambler-cli --version"
grep -qxF "data: $root/usr/share/ambler" <<< "$version" ||
  fail "the installed ambler-cli does not use the installed data"
env -u AMBLER_DATA_DIR "$root/usr/bin/ambler-sim" --version | grep -q "^ambler-sim " ||
  fail "ambler-sim --version"
QT_QPA_PLATFORM=offscreen env -u AMBLER_DATA_DIR "$root/usr/bin/ambler-gs" --version |
  grep -q "ambler-gs" || fail "ambler-gs --version"

# An evaluation from the installed tree: locus maps and binned maps of two
# simulated scans against the simulator's truth (its table: method, k,
# rmse_m, coverage, ...). The locus method must beat binning at both noise
# levels and know over 85 % of the visible cells without noise (on this 5 m,
# 30 degree view 95 %; of the rest, ground seen at a grazing angle is
# oblique) and over half with it (58 %: ground beyond 16.3 m, whose noise
# could hide a foot-sized gap, is oblique too).
env -u AMBLER_DATA_DIR "$cli" eval elevation --families course --seeds 1 --poses 5:30 \
  --noise 0,2e-4 \
  > "$scratch/eval.txt" 2> /dev/null || fail "eval elevation"
cat "$scratch/eval.txt"
# Only the pooled table: its lines start with the method.
awk '$1 == "binning" { binning[$2] = $3 }
     $1 == "locus" { locus[$2] = $3; coverage[$2] = $4 }
     END {
       n = 0
       for (k in locus) {
         n++
         if (!(locus[k] > 0 && locus[k] < binning[k] && coverage[k] > (k + 0 == 0 ? 0.85 : 0.5))) exit 1
       }
       exit n != 2
     }' "$scratch/eval.txt" || fail "eval elevation from the package: locus does not beat binning"

# The packaged sample scan maps.
env -u AMBLER_DATA_DIR "$cli" map --range "$root/usr/share/ambler/samples/scan-seed1/scan.tif" \
  --region=-5,5,5,15 --resolution 0.1 --out "$scratch/map" > /dev/null || fail "map of the sample"
[[ -s $scratch/map/elevation.tif ]] || fail "no elevation.tif from the sample"
echo "PASS"
