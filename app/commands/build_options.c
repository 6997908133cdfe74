/* build_options.c - `terrapatch build`'s options and --help (see build_options.h). */
#include "build_options.h"

#include "cli.h"
#include "options.h"

#include "tp_core.h"
#include "tp_imagery.h"

#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { OPT_PATCH = 1, OPT_RESAMPLING, OPT_FILL_FROM, OPT_IMAGERY, OPT_Z_UNIT, OPT_PART, OPT_RANGE };

static void print_help(void)
{
    fputs("usage: terrapatch build [options] SOURCE... -o NAME.tpt\n"
          "\n"
          "Builds a terrain store from any number of rasters GDAL opens (adjacent tiles of any\n"
          "format mix, a .vrt): they are mosaicked with GDAL's VRT (a later source wins where\n"
          "they overlap, gaps are nodata), or each warped onto one grid when their CRSs or post\n"
          "spacings differ; geographic sources are warped to the UTM/UPS zone of the centre.\n"
          "The grid is read in bands of rows, quantised with one global height step and built\n"
          "into a hierarchy of (2^n+1)^2 nodes; memory stays within --memory whatever the size.\n"
          "Interior voids of any size (up to --fill-max samples when given) are filled as the\n"
          "viewer fills a DEM's: interpolated (GDALFillNodata) or, with --fill-from, from a\n"
          "second raster shifted to meet the ground around each void; voids on the border\n"
          "stay nodata (never drawn), and so does a void too tall for the memory given to\n"
          "the window it is filled in (a warning says so). The store marks every filled\n"
          "sample: 'terrapatch info STORE' counts them, the viewer tints them (V).\n"
          "\n"
          "options:\n"
          "  -o, --output FILE   the store to write, NAME.tpt (written whole or not at all)\n"
          "  --patch N           node size: 17, 33, 65, 129 or 257 (default 65)\n"
          "  --crs CRS           the sources' CRS (EPSG:N, WKT, PROJ), overriding theirs\n"
          "  --resampling R      bilinear (default) or cubic, for warps\n"
          "  --fill-max N        fill interior voids up to N x N samples only (default: any\n"
          "                      size; 0 fills nothing); filled samples are marked\n"
          "  --fill-from FILE    fill voids from this raster (any CRS and resolution),\n"
          "                      shifted onto the ground around each void\n"
          "  --imagery IMAGE     then an imagery pyramid NAME.tpi of IMAGE (repeat for a\n"
          "                      mosaic, later ones on top), as 'terrapatch imagery' makes\n"
          "  --imagery-texel-shift K, --imagery-resolution M\n"
          "                      its level-0 texels: 'terrapatch imagery's --texel-shift and\n"
          "                      --resolution (default: from the finest image)\n"
          "  --height-step M     the heights' quantisation step, metres (default: 1 where\n"
          "                      every height is a whole metre, 1/16 where a warp resampled\n"
          "                      whole metres, else the finest power of two that fits);\n"
          "                      'terrapatch info STORE' states it\n"
          "  --height-range LO,HI the heights lie in LO .. HI metres (the sources' unit\n"
          "                      converted): the step follows from it, no pass reads the grid\n"
          "                      for a bound (give every part of a build in parts the same); a\n"
          "                      height outside is an error\n"
          "  --z-unit m|ft|us-ft the unit of the sources' heights, overriding theirs (band\n"
          "                      unit, else vertical CRS); feet are converted to metres\n"
          "  --allow-gaps        build even when the sources cover under half of their\n"
          "                      mosaic (refused otherwise: sources far apart are almost\n"
          "                      always a mistake, and the gaps cost time and space)\n"
          "  --memory MB         memory budget (default 1024); GDAL's cache gets a quarter;\n"
          "                      refused at once when one band of rows does not fit\n"
          "  --part I/N          build part I of N only (a strip of the hierarchy's subtrees),\n"
          "                      into a partial store that 'terrapatch merge' joins with the\n"
          "                      others into the store one build would write, byte for byte;\n"
          "                      every part must be given the same sources and options\n"
          "  --threads N         threads (default: every core)\n"
          "  --json FILE|-       statistics as JSON (samples, nodes, bytes, seconds, ...)\n"
          "  --quiet             no progress, no notes\n"
          "  -h, --help          show this help\n"
          "\n"
          "Exit status: 0 success, 1 a source could not be read or the store not written,\n"
          "2 usage error, 130/143 after SIGINT/SIGTERM (no store and no temporary file left).\n",
          stdout);
}

int tp_build_parse_options(int argc, char** argv, build_options* o)
{
    *o = (build_options){0};
    tp_build_options_init(&o->build);
    o->imagery_cli.texel_shift = TP_IMAGERY_SHIFT_AUTO;
    const tp_option options[] = {
        TP_OPT_TEXT("--output", "-o", &o->build.out),
        TP_OPT_CODE("--patch", NULL, OPT_PATCH, 1),
        TP_OPT_TEXT("--crs", NULL, &o->build.crs),
        TP_OPT_CODE("--resampling", NULL, OPT_RESAMPLING, 1),
        TP_OPT_INTEGER("--memory", &o->build.memory_mb, BUILD_MIN_MEMORY_MB, 1 << 24,
                       "megabytes, 64 or more"),
        TP_OPT_INTEGER("--fill-max", &o->build.fill_max, 0, 100000, "0 .. 100000 samples"),
        TP_OPT_CODE("--fill-from", NULL, OPT_FILL_FROM, 1),
        TP_OPT_CODE("--imagery", NULL, OPT_IMAGERY, 1),
        TP_OPT_INTEGER("--imagery-texel-shift", &o->imagery_cli.texel_shift, TP_IMAGERY_SHIFT_MIN,
                       TP_IMAGERY_SHIFT_MAX, "-8 .. 8"),
        TP_OPT_NUMBER_ABOVE("--imagery-resolution", &o->imagery_cli.resolution_m, 0, DBL_MAX,
                            "metres > 0"),
        TP_OPT_INTEGER("--threads", &o->build.threads, 1, 1024, "1 .. 1024"),
        TP_OPT_TEXT("--json", NULL, &o->json),
        TP_OPT_FLAG("--quiet", &o->build.quiet),
        TP_OPT_FLAG("--allow-gaps", &o->build.allow_gaps),
        TP_OPT_NUMBER_ABOVE("--height-step", &o->build.height_step_m, 0, 1000, "metres > 0"),
        TP_OPT_CODE("--z-unit", NULL, OPT_Z_UNIT, 1),
        TP_OPT_CODE("--part", NULL, OPT_PART, 1),
        TP_OPT_CODE("--height-range", NULL, OPT_RANGE, 1),
    };
    tp_options p;
    tp_options_init(&p, "build", argc, argv, print_help);
    tp_options_add(&p, options, TP_OPTIONS_COUNT(options), NULL, NULL);
    for (int c; (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        const char* v = p.value;
        switch (c) {
        case TP_OPTIONS_EXIT: return p.exit;
        case TP_OPTIONS_OPERAND: tp_options_keep(&p, &o->build.source_count); break;
        case OPT_PATCH:
            if (!tp_parse_int(v, 17, 257, &o->build.patch_size) ||
                ((o->build.patch_size - 1) & (o->build.patch_size - 2))) /* not 2^n + 1 */
                return tp_options_bad_value(&p, "17, 33, 65, 129 or 257"), TP_EXIT_USAGE;
            break;
        case OPT_RESAMPLING:
            if (strcmp(v, "bilinear") && strcmp(v, "cubic"))
                return tp_options_bad_value(&p, "bilinear or cubic"), TP_EXIT_USAGE;
            o->build.resampling = *v == 'c' ? TP_RESAMPLING_CUBIC : TP_RESAMPLING_BILINEAR;
            break;
        case OPT_FILL_FROM:
            if (!*v)
                return tp_options_bad_value(&p, "a raster file"), TP_EXIT_USAGE;
            o->build.fill_from = v;
            break;
        case OPT_IMAGERY:
            if (o->imagery_count == 256)
                return tp_cli_usage_at("build", "more than 256 --imagery files", "");
            o->imagery[o->imagery_count++] = v;
            break;
        case OPT_PART: {
            int i = 0, n = 0, used = 0;
            if (sscanf(v, "%d/%d%n", &i, &n, &used) != 2 || v[used] || n < 1 || n > 65536 ||
                i < 1 || i > n)
                return tp_options_bad_value(&p, "I/N, 1 <= I <= N <= 65536"), TP_EXIT_USAGE;
            o->build.part_index = i, o->build.part_count = n;
            break;
        }
        case OPT_RANGE: {
            double* r = o->build.height_range_m;
            if (!tp_parse_numbers(v, r, 2) || !(r[0] < r[1]) || r[0] < -1e5 || r[1] > 1e5)
                return tp_options_bad_value(&p, "LO,HI metres, LO < HI, within +-1e5"),
                       TP_EXIT_USAGE;
            o->build.height_range_given = 1;
            break;
        }
        case OPT_Z_UNIT:
            if (strcmp(v, "m") && strcmp(v, "ft") && strcmp(v, "us-ft"))
                return tp_options_bad_value(&p, "m, ft or us-ft"), TP_EXIT_USAGE;
            o->build.z_unit = v;
            break;
        }
    }
    const int shift_given = o->imagery_cli.texel_shift != TP_IMAGERY_SHIFT_AUTO;
    if (!o->build.source_count)
        return tp_cli_usage_at("build", "missing SOURCE", "");
    if (!o->build.out)
        return tp_cli_usage_at("build", "missing -o NAME.tpt", "");
    if (shift_given && o->imagery_cli.resolution_m > 0)
        return tp_cli_usage_at("build", "give --imagery-texel-shift or --imagery-resolution, not both", "");
    if ((shift_given || o->imagery_cli.resolution_m > 0) && !o->imagery_count)
        return tp_cli_usage_at("build", "--imagery-texel-shift and --imagery-resolution need --imagery", "");
    if (o->build.part_count && o->imagery_count)
        return tp_cli_usage_at("build", "--imagery is for the whole store: give it to "
                               "'terrapatch imagery' after 'terrapatch merge', not to a --part", "");
    o->build.sources = (const char**)(argv + 1);
    if (o->build.threads == 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        o->build.threads = n > 0 ? (int)(n > 1024 ? 1024 : n) : 1;
    }
    return -1;
}
