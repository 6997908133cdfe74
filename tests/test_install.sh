#!/bin/bash
# test_install.sh CMAKE BUILD_DIR EXE SOURCE_DATA WORK_DIR CASE: `terrapatch view` with no DEM
# finds its sample (data/lf_elev_220_mt_hood_utm.tif) wherever it is run from, and an installed
# terrapatch works on its own.
#   elsewhere  the built binary, run from an empty folder with no data/ beside it: exit 0, the
#              PNG written, the sample read from the source tree's data/
#   installed  `cmake --install BUILD_DIR --prefix WORK_DIR/prefix`: bin/terrapatch, its module
#              lib*/terrapatch/libtp_io_media.so and share/terrapatch/data/ are there; the
#              installed binary, run from / with no DEM, renders the installed sample headless
#              (the screenshot goes through the module); the same after the prefix is moved
# Each run uses a fresh --cache-dir, so `view` builds the sample's store and names its source.
set -u
CMAKE=$1 BUILD=$2 EXE=$3 SRC_DATA=$4 WORK=$5 CASE=$6
SAMPLE=lf_elev_220_mt_hood_utm.tif
rm -rf "$WORK" && mkdir -p "$WORK" && WORK=$(cd "$WORK" && pwd -P) || exit 1
fail() { echo "FAIL ($CASE): $*"; [ -f "$WORK/err" ] && { echo '--- stderr'; cat "$WORK/err"; }; exit 1; }

# view_sample TP FROM NAME: `TP view --headless` with no DEM, run in FROM; sets rc, writes
# WORK/NAME.png and WORK/err
view_sample() {
    local tp=$1 from=$2 name=$3
    (cd "$from" && timeout 120 "$tp" view --headless --size 160x120 --cache-dir "$WORK/cache_$name" \
        --screenshot "$WORK/$name.png") > "$WORK/out" 2> "$WORK/err"
    rc=$?
}
# png_ok FILE: a PNG file (its signature)
png_ok() { [ -s "$1" ] && [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; }

case "$CASE" in
elsewhere)
    mkdir -p "$WORK/empty"
    view_sample "$EXE" "$WORK/empty" elsewhere
    [ $rc -eq 0 ] || fail "view with no DEM from $WORK/empty: exit $rc"
    png_ok "$WORK/elsewhere.png" || fail "no PNG written"
    want=$(realpath "$SRC_DATA/$SAMPLE")
    grep -qF "building a store of $want " "$WORK/err" || fail "the sample read is not $want"
    ;;
installed)
    prefix=$WORK/prefix
    "$CMAKE" --install "$BUILD" --prefix "$prefix" > "$WORK/install.log" 2>&1 ||
        { cat "$WORK/install.log"; fail "cmake --install failed"; }
    [ -x "$prefix/bin/terrapatch" ] || fail "no bin/terrapatch"
    module=$(ls "$prefix"/lib*/terrapatch/libtp_io_media.so "$prefix"/lib/*/terrapatch/libtp_io_media.so 2> /dev/null | head -n 1)
    [ -n "$module" ] || fail "no lib/terrapatch/libtp_io_media.so: $(cd "$prefix" && find . -type f | head -n 20)"
    for f in "$SAMPLE" PROVENANCE.md N42E001.hgt vectors/coma_pedrosa.gpx; do
        [ -f "$prefix/share/terrapatch/data/$f" ] || fail "no share/terrapatch/data/$f"
    done
    # nothing of the build tree is needed: no module beside the binary
    [ ! -e "$prefix/bin/libtp_io_media.so" ] || fail "the module is in bin/"
    view_sample "$prefix/bin/terrapatch" / installed
    [ $rc -eq 0 ] || fail "installed view with no DEM from /: exit $rc"
    png_ok "$WORK/installed.png" || fail "no PNG written"
    grep -qF "building a store of $prefix/share/terrapatch/data/$SAMPLE " "$WORK/err" ||
        fail "the installed binary did not read the installed sample"
    # the prefix moves: everything is found relative to the binary
    mv "$prefix" "$WORK/moved"
    view_sample "$WORK/moved/bin/terrapatch" / moved
    [ $rc -eq 0 ] || fail "moved install: exit $rc"
    png_ok "$WORK/moved.png" || fail "moved install: no PNG written"
    grep -qF "building a store of $WORK/moved/share/terrapatch/data/$SAMPLE " "$WORK/err" ||
        fail "the moved install did not read its own sample"
    ;;
*)
    echo "unknown case $CASE"
    exit 2
    ;;
esac
echo "ok ($CASE)"
