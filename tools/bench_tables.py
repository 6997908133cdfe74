#!/usr/bin/env python3
"""Markdown tables for docs/PERFORMANCE.md from the JSON files the bench scripts write.

Usage:
  tools/bench_tables.py OUTDIR DEM...             tools/bench_all.sh's: every path, the static
                                                  meshes, the TINs and the sweeps per DEM
  tools/bench_tables.py --paths low OUTDIR DEM... only those paths' tables (comma-separated)
  tools/bench_tables.py --stores OUTDIR SIZE...   tools/gpu_bench.sh's: the "Real relief at
                                                  10 m" table of the stores real_SIZE.tpt
    (OUTDIR/real_SIZE_{low100,low300,high}.json from bench, OUTDIR/real_SIZE_build.json from
    build --json, OUTDIR/real_meta.json's pixel_m; a run missing leaves its cells "not run")"""
import json
import os
import sys

def load_json(out, name):
    try:
        with open(os.path.join(out, name)) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def num(v, fmt):
    """v in fmt; "n/a" for a null (not measured)."""
    return "n/a" if v is None else fmt % v


def thousands(v):
    """425 k for 425,123; 1.39 M for 1,390,000; 1,134 below 10,000."""
    if v is None:
        return "n/a"
    if v >= 1e6:
        return "%.2f M" % (v / 1e6)
    if v >= 1e4:
        return "%.0f k" % (v / 1e3)
    return "{:,.0f}".format(v)


def span(values, fmt):
    """"a–b" over the values (one value when they agree to the format), "n/a" for none."""
    vals = [v for v in values if v is not None]
    if not vals:
        return "n/a"
    lo, hi = fmt % min(vals), fmt % max(vals)
    return lo if lo == hi else "%s–%s" % (lo, hi)


def store_table(out, sizes):
    """The "Real relief at 10 m" table: one column a store, the rows of docs/PERFORMANCE.md."""
    runs = {}
    for n in sizes:
        runs[n] = {k: load_json(out, "real_%s_%s.json" % (n, k))
                   for k in ("low100", "low300", "high", "build")}
    any_run = next((r[k] for r in runs.values() for k in ("low100", "low300", "high") if r[k]),
                   None)
    if any_run:
        print("Renderer: %s; %s; τ = %g px, `--memory %.0f`.\n" % (
            any_run["renderer"], any_run["size"], any_run["configurations"][0]["tau_px"],
            any_run["memory_budget_mb"] * 1e6 / 2 ** 20))

    def head(n):
        b = runs[n]["build"]
        if b and b.get("width"):
            return "%s² (%.0f km)" % (n, (b["width"] - 1) * pixel_m(out, n) / 1000.0)
        return "%s²" % n

    def cell(n, kind, f):
        d = runs[n][kind]
        if not d:
            return "not run"
        try:
            return f(d, d["configurations"])
        except (KeyError, IndexError, TypeError):
            return "n/a"

    def first(d, c):
        return "%.1f s (%.2f + %.2f)" % (d["first_frame_ms"] / 1e3, d["store_open_ms"] / 1e3,
                                         d["gl_context_ms"] / 1e3)

    def first_all(n):
        ds = [runs[n][k] for k in ("low100", "low300", "high") if runs[n][k]]
        if not ds:
            return "not run"
        return "%s s (%s + %s)" % (
            span([d["first_frame_ms"] / 1e3 for d in ds], "%.1f"),
            span([d["store_open_ms"] / 1e3 for d in ds], "%.2f"),
            span([d["gl_context_ms"] / 1e3 for d in ds], "%.2f"))

    def err(c):
        e = c.get("max_screen_error_px")
        if e is None:
            return "not measured"
        share = c.get("error_leaf_share")
        return "%.3f px (%d frames%s)" % (
            e, c["error_frames_measured"],
            "" if share is None or share >= 1 else ", %.1f%% of the leaves" % (100 * share))

    def build(n):
        b = runs[n]["build"]
        if not b:
            return "not run"
        return "%.1f s, %.2f B/sample, peak RSS %.0f MB" % (b["seconds"], b["bytes_per_sample"],
                                                            b["rss_peak_mb"])

    rows = [
        ("build (`terrapatch build --json`)", build),
        ("first frame from the process's start (open + GL context)", first_all),
        ("fps median, low 100 m/s",
         lambda n: cell(n, "low100", lambda d, c: "%.1f" % c[0]["fps_median"])),
        ("triangles median / nodes drawn / visited",
         lambda n: cell(n, "low100", lambda d, c: "%s / %s / %s" % (
             thousands(c[0]["triangles_median"]), thousands(c[0]["nodes_drawn_median"]),
             thousands(c[0]["nodes_visited_median"])))),
        ("CPU ms median (cut + stream + uploads)",
         lambda n: cell(n, "low100", lambda d, c: "%.2f (%.2f + %.2f + %.2f)" % (
             c[0]["cpu_ms_median"], c[0]["cut_ms_median"], c[0]["stream_ms_median"],
             c[0]["upload_ms_median"]))),
        ("measured max screen error (frames without substitution)",
         lambda n: cell(n, "low100", lambda d, c: err(c[0]))),
        ("frames with substitution, 100 / 300 m/s", lambda n: "%s / %s" % (
            cell(n, "low100", lambda d, c: "%d of %d" % (c[0]["frames_with_substitution"],
                                                         d["frames"])),
            cell(n, "low300", lambda d, c: "%d of %d" % (c[0]["frames_with_substitution"],
                                                         d["frames"])))),
        ("p99 / median, 100 / 300 m/s", lambda n: "%s / %s" % (
            cell(n, "low100", lambda d, c: "%.1f" % c[0]["p99_over_median"]),
            cell(n, "low300", lambda d, c: "%.1f" % c[0]["p99_over_median"]))),
        ("high path: fps, triangles, nodes",
         lambda n: cell(n, "high", lambda d, c: "%.1f, %s, %s" % (
             c[0]["fps_median"], thousands(c[0]["triangles_median"]),
             thousands(c[0]["nodes_drawn_median"])))),
        ("high path: measured max screen error",
         lambda n: cell(n, "high", lambda d, c: err(c[0]))),
        ("distance mode, low: fps, triangles, nodes, CPU",
         lambda n: cell(n, "low100", lambda d, c: "%.1f, %s, %s, %.2f ms" % (
             c[1]["fps_median"], thousands(c[1]["triangles_median"]),
             thousands(c[1]["nodes_drawn_median"]), c[1]["cpu_ms_median"]))),
        ("GPU vertex data", lambda n: cell(n, "low100", lambda d, c: "%.1f MB" % c[0]["gpu_mb"])),
        ("RSS anonymous during the flight",
         lambda n: cell(n, "low100", lambda d, c: "%.0f MB" % max(x["rss_anon_mb"] for x in c))),
        ("RSS anonymous at start (node table mapped)",
         lambda n: cell(n, "low100", lambda d, c: "%.0f MB" % d["base_rss_anon_mb"])),
        ("decoded nodes resident (stream)",
         lambda n: cell(n, "low100", lambda d, c: "%.0f MB" % c[0]["resident_mb"])),
        ("peak RSS", lambda n: span([runs[n][k]["peak_rss_mb"] for k in ("low100", "low300", "high")
                                     if runs[n][k]], "%.0f") + " MB"),
    ]
    print("| | " + " | ".join(head(n) for n in sizes) + " |")
    print("|---|" + "---:|" * len(sizes))
    for name, f in rows:
        print("| %s | %s |" % (name, " | ".join(f(n) for n in sizes)))
    print()


def pixel_m(out, n):
    """The mosaic's post spacing (m): OUTDIR/real_meta.json's pixel_m (gpu_bench.sh), else 10."""
    return (load_json(out, "real_meta.json") or {}).get("pixel_m", 10.0)


def label(c):
    if c["lod_mode"] == "error":
        return "error τ=%g" % c["tau_px"]
    if c["lod_mode"] == "distance":
        return "distance"
    return "full"


def dem_tables(out, dems, paths=("low", "high", "orbit"), everything=True):
    def load(name, kind):
        return load_json(out, "%s_%s.json" % (name, kind))

    for path in paths:
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
                print("| %s | %s | %d | %s | %.1f | %.1f | %.3f | %.1f | %.0f | %s | %s | %s | %s |" % (
                    f, grid, d["patches"], label(c), c["fps_median"], c["frame_ms_median"],
                    c["cpu_ms_median"], c["draw_ms_median"], c["triangles_median"],
                    num(c["max_screen_error_px"], "%.2f"), num(c["rms_screen_error_px"], "%.3f"),
                    num(c["max_vertical_error_m"], "%.1f"), num(c["rms_vertical_error_m"], "%.2f")))
            oracle = d.get("oracle_triangles_median")
            print("| | | | **error vs full: %.2f×** | | | | | %s | | | | |" % (
                d["speedup_vs_full"],
                "best per-patch levels: %.0f" % oracle if oracle else ""))
        print()
    if not everything:
        return

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
        # the store families: the DEM's store through its cut, lattice and TIN nodes, per tau
        store = {c["tau_px"]: c for c in d["configurations"] if c.get("family") == "store"}
        tin = {c["tau_px"]: c for c in d["configurations"] if c.get("family") == "store+tin"}
        if store and tin:
            print("Over its store (error mode): %s.\n" % ", ".join(
                "τ %g → lattice %.1f fps, %.0f triangles, max %.2f px; TIN nodes %.1f fps, %.0f "
                "triangles (%.0f %%), max %.2f px" % (
                    t, store[t]["fps_median"], store[t]["triangles_median"],
                    store[t]["max_screen_error_px"], tin[t]["fps_median"],
                    tin[t]["triangles_median"],
                    100 * tin[t]["triangles_median"] / store[t]["triangles_median"],
                    tin[t]["max_screen_error_px"])
                for t in sorted(store) if t in tin))


def main(argv):
    if len(argv) >= 2 and argv[0] == "--stores":
        store_table(argv[1], argv[2:])
        return 0
    if len(argv) >= 3 and argv[0] == "--paths":
        dem_tables(argv[2], argv[3:], tuple(argv[1].split(",")), everything=False)
        return 0
    if len(argv) < 1 or argv[0].startswith("-"):
        sys.stderr.write(__doc__)
        return 2
    dem_tables(argv[0], argv[1:])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
