#!/bin/bash
# prints the markdown table of render grids for every DEM in data/
cd "$(dirname "$0")/.."
echo "| DEM | CRS as read | render CRS | zone | render grid | spacing (m) | warp error max / RMS (m) | voids filled | large voids | outside | to WGS84 |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for f in N41E001.hgt N42E001.hgt N42E001.dt1 mt_rainier_90m.tif lf_elev_220_mt_hood_utm.tif storml_elev_orig.tif storml_elev.tif craterlake-elev-16bit-30m.tif front_range_srtmgl3_758.asc front_range_srtmgl3_144.asc ps_height_1k.png; do
  extra=""
  case $f in front_range*) extra="--crs EPSG:4326";; ps_height*) extra="--spacing 160 --zscale 0.1";; esac
  ./build/terrapatch info --json $extra data/$f 2>/dev/null | python3 -c '
import json,sys
d=json.load(sys.stdin); f=sys.argv[1]; extra=sys.argv[2]
src = ("EPSG:%d"%d["epsg"]) if d["epsg"] else "none"
w = "%.3g / %.3g"%(d["warp_max_error_m"], d["warp_rms_error_m"]) if d["warped"] else "not warped"
acc = d["datum_accuracy_m"]
note = d["datum_to_wgs84"] + ("" if acc==0 else (" (%.3g m)"%acc if acc>0 else " (ballpark)"))
print("| %s%s | %s | %s | %s | %dx%d | %.2f | %s | %d | %d | %d | %s |"%(f, (" `"+extra+"`") if extra else "", src, d["render_crs_name"], d["utm_zone"] or "-", d["render_grid"][0], d["render_grid"][1], d["spacing_m"], w, d["void_filled"], d["large_void_samples"], d["outside_samples"], note))
' $f "$extra"
done
