#!/usr/bin/env python3
"""Markdown tables for docs/PERFORMANCE.md from the JSON files tools/bench_all.sh writes.
Usage: tools/bench_tables.py OUTDIR DEM..."""
import json
import os
import sys

out, dems = sys.argv[1], sys.argv[2:]


def load(name, kind):
    try:
        with open(os.path.join(out, "%s_%s.json" % (name, kind))) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def label(c):
    if c["lod_mode"] == "error":
        return "error τ=%g" % c["tau_px"]
    if c["lod_mode"] == "distance":
        return "distance"
    return "full"


for path in ("low", "high", "orbit"):
    print("### `--path %s`\n" % path)
    print("| DEM | render grid | patches | configuration | fps | frame ms | CPU ms | draw ms "
          "| triangles | max px | RMS px | max m | RMS m |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for f in dems:
        name = f.rsplit(".", 1)[0] + "_" + f.rsplit(".", 1)[1]
        d, info = load(name, path), load(name, "info")
        if not d or not info:
            print("| %s | not run | | | | | | | | | | | |" % f)
            continue
        grid = "%dx%d" % tuple(info["render_grid"])
        for c in d["configurations"]:
            print("| %s | %s | %d | %s | %.1f | %.1f | %.3f | %.1f | %.0f | %.2f | %.3f | %.1f | %.2f |" % (
                f, grid, d["patches"], label(c), c["fps_median"], c["frame_ms_median"],
                c["cpu_ms_median"], c["draw_ms_median"], c["triangles_median"],
                c["max_screen_error_px"], c["rms_screen_error_px"], c["max_vertical_error_m"],
                c["rms_vertical_error_m"]))
        oracle = d.get("oracle_triangles_median")
        print("| | | | **error vs full: %.2f×** | | | | | %s | | | | |" % (
            d["speedup_vs_full"],
            "best per-patch levels: %.0f" % oracle if oracle else ""))
    print()

print("### Static meshes (`--static --max-error 1,5,20`)\n")
print("| DEM | full mesh triangles | bound m | triangles | % of full | points | select s | mesh s "
      "| measured max m | measured RMS m |")
print("|---|---|---|---|---|---|---|---|---|---|")
for f in dems:
    name = f.rsplit(".", 1)[0] + "_" + f.rsplit(".", 1)[1]
    d = load(name, "static")
    if not d:
        print("| %s | not run | | | | | | | | |" % f)
        continue
    for s in d["static"]:
        if s.get("mesher", "patches") != "patches":
            continue  # the TIN rows: their own table below
        if s["below_quantisation"]:
            print("| %s | %d | %g | below the quantisation error (%.3g m) | | | | | | |" % (
                f, d["full_triangles"], s["max_error_m"], d["quantisation_error_m"]))
            continue
        print("| %s | %d | %g | %d | %.1f | %d | %.3f | %.3f | %.3f | %.3f |" % (
            f, d["full_triangles"], s["max_error_m"], s["triangles"],
            100.0 * s["triangles"] / max(d["full_triangles"], 1), s["points"], s["select_s"],
            s["mesh_s"], s["measured_max_error_m"], s["measured_rms_error_m"]))
print()

print("### Error-bounded TINs (the same runs' TIN rows)\n")
print("| DEM | grid | mesher | bound m | triangles | points | time s | true max m | uncovered | peak MiB |")
print("|---|---|---|---|---|---|---|---|---|---|")
for f in dems:
    name = f.rsplit(".", 1)[0] + "_" + f.rsplit(".", 1)[1]
    d = load(name, "static")
    if not d or "tin_grid" not in d:
        continue
    g = d["tin_grid"]
    for s in d["static"]:
        if s.get("mesher") == "patches":
            continue
        print("| %s | %s %dx%d | %s | %g | %d | %d | %.3f | %.4f | %d | %s |" % (
            f, g["grid"], g["width"], g["height"], s["mesher"], s["max_error_m"], s["triangles"],
            s["points"],
            s["time_s"], s["measured_max_error_m"], s["uncovered_samples"],
            "n/a" if s["peak_mib"] is None else "%.1f" % s["peak_mib"]))
print()

print("### Sweeps (`--sweep`, low path)\n")
for f in dems:
    name = f.rsplit(".", 1)[0] + "_" + f.rsplit(".", 1)[1]
    d = load(name, "sweep")
    if not d:
        print("* %s: not run" % f)
        continue
    full = d["full_res"]["fps_median"]
    best = {}
    # the error mode with vertex moving (the sweep also has "error+add" rows of lod_mode error)
    moving = [c for c in d["configurations"]
              if c["lod_mode"] == "error" and c.get("family", "error") == "error"]
    for c in moving:
        best[c["tau_px"]] = c
    four = [c for c in moving if c["fps_median"] >= 4 * full]
    tau4 = min((c["tau_px"] for c in four), default=None)
    print("#### %s\n" % f)
    print("![fps against measured error, %s](img/bench/%s_sweep.png)\n" % (f, name))
    print("Full resolution %.1f fps. Error mode: %s. 4× full resolution first reached at %s.\n" % (
        full, ", ".join("τ %g → %.1f fps, max %.2f px" % (t, c["fps_median"], c["max_screen_error_px"])
                        for t, c in sorted(best.items())),
        "τ = %g px" % tau4 if tau4 else "no τ of the grid"))
