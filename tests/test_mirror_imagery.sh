#!/bin/bash
# test_mirror_imagery.sh TOOL TERRAPATCH DATA_DIR WORK_DIR CASE: tools/make_mirror_imagery.py
# (the large mirrored test image of docs/imagery.md) and `terrapatch imagery` / `build
# --imagery` on it and on the real Crater Lake imagery. Needs the GDAL command-line tools.
#   mirror   a 2000-pixel-wide mirror over craterlake-elev-16bit-30m.tif's extent: size, CRS and
#            extent are the DEM's (gdalinfo); pixels of the first copy are the image's, the
#            second copy (across the seam) its mirror image, the copy below mirrored top-bottom;
#            --keep-alpha keeps 4 bands; usage errors exit 2 and write nothing
#   build    `build --imagery` writes NAME.tpt and NAME.tpi, which `info` describes (and
#            names beside the store);
#            `imagery` of the store and the mirror at --texel-shift -1 agrees with the sizes
#            the grid gives, as does `build --imagery-texel-shift -1`; a missing image fails before the store is built, leaving nothing
set -u
TOOL=$1 TP=$2 DATA=$3 WORK=$4 CASE=$5
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAIL ($CASE): $*"; for f in out err; do [ -s $f ] && { echo "--- $f"; cat $f; }; done; exit 1; }
for t in gdalinfo gdallocationinfo gdal_translate; do
    command -v $t > /dev/null ||
        fail "$t not found: the GDAL command-line tools (gdal-bin) are missing; \`make deps\` installs them"
done
DEM=$DATA/craterlake-elev-16bit-30m.tif IMG=$DATA/craterlake-imagery-30m.tif
[ -f "$DEM" ] && [ -f "$IMG" ] || fail "craterlake files not found in $DATA (TP_SHARED_DATA_DIR)"
size() { gdalinfo "$1" | sed -n 's/^Size is \([0-9]*\), \([0-9]*\)$/\1 \2/p'; }
# px FILE X Y: the bands' values of pixel (X, Y), space-separated
px() { gdallocationinfo -valonly "$1" "$2" "$3" | tr '\n' ' '; }

case "$CASE" in
mirror)
    python3 "$TOOL" 2000 m --like "$DEM" > out 2> err || fail "the tool failed"
    V=m/imagery_2000.vrt
    read W H <<< "$(size "$V")"
    # the DEM is 429 x 279 pixels: 2000 across, 279/429 of that down
    [ "$W" = 2000 ] && [ "$H" = $(( (2000 * 279 + 214) / 429 )) ] || fail "size $W x $H"
    gdalinfo "$V" | grep -q 'ID\["EPSG",4326\]' || fail "not the DEM's CRS"
    o1=$(gdalinfo "$DEM" | sed -n 's/^Origin = //p') o2=$(gdalinfo "$V" | sed -n 's/^Origin = //p')
    [ "$o1" = "$o2" ] || fail "origin $o2, the DEM's $o1"
    [ "$(gdalinfo "$V" | grep -c '^Band ')" = 3 ] || fail "not 3 bands"
    for xy in "0 0" "100 50" "428 278" "200 7"; do
        set -- $xy
        want=$(px "$IMG" $1 $2 | cut -d' ' -f1-3)
        [ "$(px "$V" $1 $2 | cut -d' ' -f1-3)" = "$want" ] || fail "pixel ($1, $2)"
        # across the right seam: column 429 + k mirrors 428 - k; down: row 279 + k mirrors 278 - k
        [ "$(px "$V" $((857 - $1)) $2 | cut -d' ' -f1-3)" = "$want" ] || fail "mirror x of ($1, $2)"
        [ "$(px "$V" $1 $((557 - $2)) | cut -d' ' -f1-3)" = "$want" ] || fail "mirror y of ($1, $2)"
    done
    python3 "$TOOL" --keep-alpha 1000 a --like "$DEM" > out 2> err || fail "--keep-alpha failed"
    [ "$(gdalinfo a/imagery_1000.vrt | grep -c '^Band ')" = 4 ] || fail "--keep-alpha: not 4 bands"
    for bad in "1 x --like $DEM" "abc x --like $DEM" "100 x" "100 x --like /nonexistent.tif"; do
        python3 "$TOOL" $bad > out 2> err
        rc=$?
        [ $rc -ne 0 ] && [ -s err ] || fail "'$bad' exited $rc without a message"
        [ -e x/imagery_100.vrt ] && fail "'$bad' wrote a VRT"
    done
    ;;
build)
    "$TP" build --quiet "$DEM" -o c.tpt --imagery "$IMG" --json b.json > out 2> err || fail "build --imagery"
    [ -s c.tpt ] && [ -s c.tpi ] || fail "no c.tpt or c.tpi"
    "$TP" info c.tpi > out 2> err || fail "info c.tpi"
    grep -q '^checked: .* 0 damaged' out && grep -q '^level 0 ' out || fail "info c.tpi says"
    "$TP" info c.tpt > out 2> err || fail "info c.tpt"
    grep -q '^imagery: .*c.tpi' out || fail "info c.tpt does not name c.tpi"
    python3 "$TOOL" 1716 m --like "$DEM" > out 2> err || fail "the tool failed"
    "$TP" imagery --quiet --texel-shift -1 --json i.json c.tpt m/imagery_1716.vrt -o half.tpi > out 2> err ||
        fail "imagery"
    # the store's grid: 434 x 384 posts (terrapatch info), so level 0 is 217 x 192, one level
    grep -q '"width": 217' i.json && grep -q '"height": 192' i.json && grep -q '"levels": 1' i.json ||
        fail "sizes in $(cat i.json)"
    # build's own --imagery-texel-shift: the same half-resolution level 0
    "$TP" build --quiet "$DEM" -o e.tpt --imagery "$IMG" --imagery-texel-shift -1 > out 2> err ||
        fail "build --imagery-texel-shift -1"
    "$TP" info e.tpi > out 2> err || fail "info e.tpi"
    grep -q '^level 0 *217 *x *192 ' out || fail "build --imagery-texel-shift -1: $(grep '^level 0' out)"
    "$TP" build --quiet "$DEM" -o d.tpt --imagery /nonexistent.tif > out 2> err
    [ $? = 1 ] && grep -q '/nonexistent.tif' err || fail "a missing image: $(cat err)"
    [ -e d.tpt ] || [ -e d.tpi ] && fail "a missing image left a file"
    "$TP" imagery c.tpt > out 2> err
    [ $? = 2 ] || fail "imagery without an image did not exit 2"
    ls | grep -q '\.tmp' && fail "a temporary file was left"
    ;;
*) fail "unknown case" ;;
esac
echo "ok ($CASE)"
