#!/bin/bash
# test_mirror_dem.sh TOOL DATA_DIR WORK_DIR CASE: tools/make_mirror_dem.py, the large mirrored
# test DEMs of docs/PERFORMANCE.md ("Large terrains"), made from the real N42E001.hgt. Needs the
# GDAL command-line tools (gdal-bin): without them every case fails, saying `make deps`.
#   seams    4097^2 (three or four copies a side): size, CRS, pixel and origin from gdalinfo; every seam
#            continuous: the seam post is the grid's edge post, its neighbours mirror each
#            other, no repeated sample (a flat step) and no jump larger than inside the tile;
#            400 posts over all four orientations equal the grid's post they mirror
#   small    SIZE 2 (one cropped copy); --keep-voids keeps the tile's voids, the default fills;
#            a tile already in its UTM zone keeps its posts
#   errors   SIZE 1, a SIZE that is not a number, a missing tile, a tile without a CRS, missing GDAL tools: exit
#            non-zero with a message naming the problem, nothing written
set -u
TOOL=$1 DATA=$2 WORK=$3 CASE=$4
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAIL ($CASE): $*"; for f in out err; do [ -s $f ] && { echo "--- $f"; cat $f; }; done; exit 1; }
for t in gdalinfo gdallocationinfo gdal_translate gdalwarp gdaltransform gdal_fillnodata.py; do
    command -v $t > /dev/null ||
        fail "$t not found: the GDAL command-line tools (gdal-bin) are missing; \`make deps\` installs them"
done
TILE=$DATA/N42E001.hgt
[ -f "$TILE" ] || fail "$TILE not found (TP_SHARED_DATA_DIR)"

# size FILE: "W H" from gdalinfo
size() { gdalinfo "$1" | sed -n 's/^Size is \([0-9]*\), \([0-9]*\)$/\1 \2/p'; }
# strip FILE X Y W H: the samples of a window, one row per line (AAIGrid body)
strip() { gdal_translate -q -of AAIGrid -srcwin "$2" "$3" "$4" "$5" "$1" strip.asc && tail -n "$5" strip.asc; }

case "$CASE" in
seams)
    N=4097
    "$TOOL" $N . "$TILE" > out 2> err || fail "exit $?"
    VRT=mirror_$N.vrt BASE=N42E001_filled_0.bil
    [ -f $VRT ] && [ -f $BASE ] || fail "no $VRT or $BASE"
    # The VRT is small: it references the four copies, it holds no samples.
    [ "$(stat -c %s $VRT)" -lt 100000 ] || fail "$VRT is $(stat -c %s $VRT) bytes"
    gdalinfo $VRT > info || fail "gdalinfo $VRT failed"
    grep -q "^Size is $N, $N$" info || fail "not ${N}x$N: $(grep '^Size' info)"
    grep -q 'ID\["EPSG",32631\]' info || fail "CRS is not EPSG:32631 (UTM 31N, the tile's zone)"
    grep -q '^Pixel Size = (10.000000000000000,-10.000000000000000)$' info || fail "pixel is not 10 m"
    # centred on the central meridian (E 500000) at N 4985000 (45 degrees): half 20485 m
    grep -q '^Origin = (479515.000000000000000,5005485.000000000000000)$' info ||
        fail "origin: $(grep '^Origin' info)"
    read -r W H < <(size $BASE)
    [ "$W" -gt 1000 ] && [ "$H" -gt 1000 ] || fail "base grid ${W}x$H, expected a 1201^2 tile's ~1.2k x 1.6k"
    SX=$((W - 1)) SY=$((H - 1))
    [ $((2 * SX)) -lt $N ] && [ $((2 * SY)) -lt $N ] || fail "expected three or more copies a side"

    # Column seams at SX (base | left-right flip) and 2*SX (flip | base), row seams likewise:
    # a 7-post window across each, as rows of text; the base's own last / first posts beside.
    for s in $SX $((2 * SX)); do
        strip $VRT $((s - 3)) 0 7 $N > across || fail "gdal_translate across column $s"
        if [ $s = $SX ]; then edge=$((W - 1)); else edge=0; fi
        strip $BASE $edge 0 1 $H > edge
        awk -v s=$s -v H=$H '
            NR == FNR { e[FNR] = $1; next }
            { for (k = 1; k <= 3; k++) if ($(4 + k) != $(4 - k)) { printf "row %d: post %d is %s, its mirror %d is %s\n", FNR - 1, s + k, $(4 + k), s - k, $(4 - k); bad = 1; exit } }
            FNR <= H && $4 != e[FNR] { printf "row %d: seam post %s is not the grid edge post %s\n", FNR - 1, $4, e[FNR]; bad = 1; exit }
            { d = $4 - $3; if (d < 0) d = -d; if (d > max) max = d; if (d == 0) same++ }
            END { if (bad) exit 1; if (same > FNR / 100) { printf "%d of %d rows repeat the seam post (a flat step)\n", same, FNR; exit 1 }
                  printf "%.3f %d\n", max, same }' edge across > seam || fail "column seam $s: $(cat seam)"
        # no jump: the step onto the seam is no larger than the largest step inside the grid
        # near that edge (the 8 columns beside it; N42E001 has cliffs of ~200 m per post)
        if [ $s = $SX ]; then x0=$((W - 8)); else x0=0; fi
        inside=$(strip $BASE $x0 0 8 $H | awk '{ for (i = 2; i <= NF; i++) { d = $i - $(i - 1); if (d < 0) d = -d; if (d > m) m = d } } END { print m }')
        read -r step same < seam
        awk -v a="$step" -v b="$inside" 'BEGIN { exit !(a <= b && a > 0) }' ||
            fail "column seam $s: max step $step m, inside the grid $inside m"
        echo "column seam $s: max step $step m (inside $inside m), $same equal pairs"
    done
    for s in $SY $((2 * SY)); do
        strip $VRT 0 $((s - 3)) $N 7 > across || fail "gdal_translate across row $s"
        if [ $s = $SY ]; then edge=$((H - 1)); else edge=0; fi
        strip $BASE 0 $edge $W 1 > edge
        awk -v s=$s -v W=$W '
            { for (i = 1; i <= NF; i++) z[FNR, i] = $i }
            END {
                for (i = 1; i <= NF; i++) {
                    for (k = 1; k <= 3; k++) if (z[4 + k, i] != z[4 - k, i]) { printf "column %d: row %d differs from its mirror\n", i - 1, s + k; exit 1 }
                    d = z[4, i] - z[3, i]; if (d < 0) d = -d; if (d == 0) same++
                }
                if (same > NF / 100) { printf "%d of %d columns repeat the seam post\n", same, NF; exit 1 }
            }' across || fail "row seam $s"
        # the seam row is the grid edge row (the first W posts of the mosaic row)
        head -1 edge | awk -v W=$W '{ for (i = 1; i <= W; i++) printf "%s ", $i; print "" }' > e1
        sed -n 4p across | awk -v W=$W '{ for (i = 1; i <= W; i++) printf "%s ", $i; print "" }' > e2
        cmp -s e1 e2 || fail "row seam $s: not the grid's edge row"
    done

    # 400 posts anywhere: post (x, y) is the grid's (m(x, W), m(y, H)), m(i, n) the reflection
    # of i into 0..n-1 with period 2(n-1); all four orientations are hit.
    awk -v N=$N -v W=$W -v H=$H 'function m(i, n) { i %= 2 * (n - 1); return i < n ? i : 2 * (n - 1) - i }
        BEGIN { srand(12); for (k = 0; k < 400; k++) { x = int(rand() * N); y = int(rand() * N); print x, y > "at_mosaic"; print m(x, W), m(y, H) > "at_base"; q[int(x / (W - 1)) % 2, int(y / (H - 1)) % 2]++ }
                if (!q[0, 0] || !q[1, 0] || !q[0, 1] || !q[1, 1]) exit 1 }' || fail "points miss an orientation"
    gdallocationinfo -valonly $VRT < at_mosaic > z_mosaic && gdallocationinfo -valonly $BASE < at_base > z_base ||
        fail "gdallocationinfo failed"
    [ "$(wc -l < z_mosaic)" = 400 ] || fail "got $(wc -l < z_mosaic) values for 400 posts"
    cmp -s z_mosaic z_base || fail "posts differ from the grid posts they mirror: $(paste at_mosaic z_mosaic z_base | awk '$3 != $4' | head -3)"
    # relief everywhere: no voids left in the filled grid
    gdalinfo -stats $BASE | grep -q 'STATISTICS_VALID_PERCENT=100$' || fail "the filled grid has voids" ;;
small)
    "$TOOL" 2 . "$TILE" > out 2> err || fail "exit $?"
    grep -q "^Size is 2, 2$" <(gdalinfo mirror_2.vrt) || fail "mirror_2.vrt is not 2x2"
    [ "$(printf '1 1\n' | gdallocationinfo -valonly mirror_2.vrt)" = "$(printf '1 1\n' | gdallocationinfo -valonly N42E001_filled_0.bil)" ] ||
        fail "post (1, 1) is not the grid's"
    # --keep-voids: the tile's voids stay (N42E001 has 7652 void posts), in their own files
    "$TOOL" --keep-voids 2 . "$TILE" > out 2> err || fail "--keep-voids: exit $?"
    [ -f N42E001_voids_0.bil ] || fail "no N42E001_voids_0.bil"
    gdalinfo -stats N42E001_voids_0.bil | grep -q 'STATISTICS_VALID_PERCENT=99\.' || fail "--keep-voids: expected 99.x% valid"
    gdalinfo -stats N42E001_filled_0.bil | grep -q 'STATISTICS_VALID_PERCENT=100$' || fail "the filled grid has voids"
    # A tile already in its UTM zone (storml_elev.tif, 143x107, EPSG:32612) keeps its own posts:
    # same size, same values (bilinear at a post is the post), no half-post shift.
    "$TOOL" 2 . "$DATA/storml_elev.tif" > out 2> err || fail "storml_elev.tif: exit $?"
    [ "$(size storml_elev_filled_0.bil)" = "143 107" ] || fail "storml_elev.tif's grid is $(size storml_elev_filled_0.bil), not 143 107"
    printf '0 0\n142 0\n0 106\n142 106\n71 53\n5 100\n' > at
    gdallocationinfo -valonly "$DATA/storml_elev.tif" < at > z_tile
    gdallocationinfo -valonly storml_elev_filled_0.bil < at | awk '{ printf "%.6g\n", $1 }' > z_grid
    awk '{ printf "%.6g\n", $1 }' z_tile | cmp -s - z_grid || fail "storml_elev.tif's posts moved: $(paste z_tile z_grid | tr '\n' ' ')" ;;
errors)
    expect_error() { # expect_error PATTERN ARGS...: non-zero exit, PATTERN on stderr, no VRT
        local pat=$1; shift
        rm -rf o; "$@" > out 2> err && fail "$* succeeded"
        grep -q "$pat" err || fail "$*: no '$pat' on stderr"
        [ -z "$(ls o/*.vrt 2> /dev/null)" ] || fail "$*: wrote a VRT"
    }
    expect_error "SIZE must be at least 2, got 1" "$TOOL" 1 o "$TILE"
    expect_error "SIZE must be a whole number" "$TOOL" 8k o "$TILE"
    expect_error "span 1000 km" "$TOOL" 100001 o "$TILE"
    expect_error "tile .*/no_such.hgt not found" "$TOOL" 8193 o "$DATA/no_such.hgt"
    expect_error "expected SIZE OUT_DIR" "$TOOL" 8193
    expect_error "front_range_srtmgl3_144.asc has no CRS" "$TOOL" 8193 o "$DATA/front_range_srtmgl3_144.asc"
    # no GDAL tools on the PATH: only python3
    mkdir -p bin && ln -sf "$(python3 -c "import sys; print(sys.executable)")" bin/python3
    expect_error "gdalinfo not found.*make deps" env PATH="$PWD/bin" python3 "$TOOL" 8193 o "$TILE"
    "$TOOL" --help > out 2> err || fail "--help: exit $?"
    grep -q "compressed horizontally" out || fail "--help does not explain the relief" ;;
*) fail "unknown case" ;;
esac
echo "ok ($CASE)"
