#!/usr/bin/env bash
# The installed tool renders the default map from any working directory, as the build tree's
# does: `cmake --install` into a temporary prefix, the CPack .deb unpacked with dpkg-deb, and,
# only as root in CI (the CI variable set, as CI services set it) where no brushtrace package is
# installed yet, the .deb installed with dpkg -i and removed again afterwards.
# Usage: install_test.sh BUILD_DIR
set -euo pipefail
build=$(realpath "$1")
tmp=$(mktemp -d)
installed_deb=0
cleanup() {
  if ((installed_deb)); then dpkg -r brushtrace >/dev/null; fi
  rm -rf "$tmp"
}
trap cleanup EXIT

args=(render -o out.png --size 64x36 --spp 2 --backend cpu)
mkdir "$tmp/reference"
(cd "$tmp/reference" && "$build/brushtrace" "${args[@]}" --quiet)

# Runs brushtrace at $1 from an empty folder that is neither the source nor the build tree, and
# compares its image with the build tree's: same options and seed give the same pixels, and a
# missing texture would not.
renders_default_map() {
  local exe=$1 cwd
  cwd=$(mktemp -d "$tmp/cwd.XXXXXX")
  (cd "$cwd" && "$exe" "${args[@]}" >"$cwd/log" 2>&1) || { cat "$cwd/log"; echo "FAIL: $exe render failed"; exit 1; }
  grep -q "(info_intermission)" "$cwd/log" || { cat "$cwd/log"; echo "FAIL: $exe did not open maps/start.map"; exit 1; }
  idiff -q "$tmp/reference/out.png" "$cwd/out.png" >/dev/null || { echo "FAIL: $exe drew another image"; exit 1; }
  echo "ok: $exe renders the default map from $cwd"
}

cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
renders_default_map "$tmp/prefix/bin/brushtrace"
help="$tmp/prefix/share/doc/brushtrace/brushtrace-help.txt"
grep -q "Usage: brushtrace render" "$help" || { echo "FAIL: no help text of render in $help"; exit 1; }
if grep -q "$build" "$help"; then echo "FAIL: $help names the build folder"; exit 1; fi

(cd "$tmp" && cpack --config "$build/CPackConfig.cmake" -B "$tmp/package" >/dev/null)
deb=$(ls "$tmp"/package/brushtrace_*.deb)
control=$(dpkg-deb -I "$deb")
# Depends from dpkg-shlibdeps: the image libraries brushtrace links, and no OpenImageIO (issue 21).
{ grep -q "Depends: .*libopenexr" <<<"$control" && grep -q "Depends: .*libpng16-16" <<<"$control"; } ||
  { echo "$control"; echo "FAIL: $deb has no Depends"; exit 1; }
if grep -qi "openimageio" <<<"$control"; then echo "$control"; echo "FAIL: $deb depends on OpenImageIO"; exit 1; fi
dpkg-deb -x "$deb" "$tmp/unpacked"
renders_default_map "$tmp/unpacked/usr/bin/brushtrace"

if [[ $(id -u) -eq 0 && -n "${CI:-}" ]] && ! dpkg-query -W brushtrace >/dev/null 2>&1 && [[ ! -e /usr/bin/brushtrace ]]; then
  installed_deb=1
  dpkg -i "$deb" >/dev/null
  renders_default_map /usr/bin/brushtrace
else
  echo "dpkg -i skipped: only as root with CI set and no brushtrace installed"
fi
