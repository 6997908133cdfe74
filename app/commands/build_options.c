/* build_options.c - `terrapatch build`'s options and --help (see build_options.h). */
#include "build_options.h"

#include "cli.h"

#include "tp_core.h"
#include "tp_imagery.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum {
    OPT_CRS = 256,
    OPT_RESAMPLING,
    OPT_MEMORY,
    OPT_THREADS,
    OPT_JSON,
    OPT_QUIET,
    OPT_PATCH,
    OPT_FILL_MAX,
    OPT_FILL_FROM,
    OPT_IMAGERY,
    OPT_IMAGERY_SHIFT,
    OPT_IMAGERY_RESOLUTION,
    OPT_ALLOW_GAPS,
    OPT_Z_UNIT
};

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
          "  --z-unit m|ft|us-ft the unit of the sources' heights, overriding theirs (band\n"
          "                      unit, else vertical CRS); feet are converted to metres\n"
          "  --allow-gaps        build even when the sources cover under half of their\n"
          "                      mosaic (refused otherwise: sources far apart are almost\n"
          "                      always a mistake, and the gaps cost time and space)\n"
          "  --memory MB         memory budget (default 1024); GDAL's cache gets a quarter;\n"
          "                      refused at once when one band of rows does not fit\n"
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
    static const struct option longs[] = {
        {"output", required_argument, NULL, 'o'},
        {"patch", required_argument, NULL, OPT_PATCH},
        {"crs", required_argument, NULL, OPT_CRS},
        {"resampling", required_argument, NULL, OPT_RESAMPLING},
        {"memory", required_argument, NULL, OPT_MEMORY},
        {"fill-max", required_argument, NULL, OPT_FILL_MAX},
        {"fill-from", required_argument, NULL, OPT_FILL_FROM},
        {"imagery", required_argument, NULL, OPT_IMAGERY},
        {"imagery-texel-shift", required_argument, NULL, OPT_IMAGERY_SHIFT},
        {"imagery-resolution", required_argument, NULL, OPT_IMAGERY_RESOLUTION},
        {"threads", required_argument, NULL, OPT_THREADS},
        {"json", required_argument, NULL, OPT_JSON},
        {"quiet", no_argument, NULL, OPT_QUIET},
        {"allow-gaps", no_argument, NULL, OPT_ALLOW_GAPS},
        {"z-unit", required_argument, NULL, OPT_Z_UNIT},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    *o = (build_options){0};
    tp_build_options_init(&o->build);
    o->imagery_cli.texel_shift = TP_IMAGERY_SHIFT_AUTO;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":ho:", longs, NULL)) != -1) {
        switch (c) {
        case 'o': o->build.out = optarg; break;
        case OPT_PATCH:
            if (!tp_parse_int(optarg, 17, 257, &o->build.patch_size) ||
                (o->build.patch_size != 17 && o->build.patch_size != 33 && o->build.patch_size != 65 &&
                 o->build.patch_size != 129 && o->build.patch_size != 257))
                return tp_option_error("build", "--patch", "17, 33, 65, 129 or 257", optarg),
                       TP_EXIT_USAGE;
            break;
        case OPT_CRS: o->build.crs = optarg; break;
        case OPT_RESAMPLING:
            if (!strcmp(optarg, "bilinear"))
                o->build.resampling = TP_RESAMPLING_BILINEAR;
            else if (!strcmp(optarg, "cubic"))
                o->build.resampling = TP_RESAMPLING_CUBIC;
            else
                return tp_option_error("build", "--resampling", "bilinear or cubic", optarg),
                       TP_EXIT_USAGE;
            break;
        case OPT_MEMORY:
            if (!tp_parse_int(optarg, BUILD_MIN_MEMORY_MB, 1 << 24, &o->build.memory_mb))
                return tp_option_error("build", "--memory", "megabytes, 64 or more", optarg),
                       TP_EXIT_USAGE;
            break;
        case OPT_FILL_MAX:
            if (!tp_parse_int(optarg, 0, 100000, &o->build.fill_max))
                return tp_option_error("build", "--fill-max", "0 .. 100000 samples", optarg),
                       TP_EXIT_USAGE;
            break;
        case OPT_FILL_FROM:
            if (!*optarg)
                return tp_option_error("build", "--fill-from", "a raster file", optarg),
                       TP_EXIT_USAGE;
            o->build.fill_from = optarg;
            break;
        case OPT_IMAGERY:
            if (o->imagery_count == 256)
                return tp_cli_usage_at("build", "more than 256 --imagery files", "");
            o->imagery[o->imagery_count++] = optarg;
            break;
        case OPT_IMAGERY_SHIFT:
            if (!tp_imagery_cli_parse_shift("build", "--imagery-texel-shift", optarg,
                                            &o->imagery_cli))
                return TP_EXIT_USAGE;
            o->imagery_shift_given = 1;
            break;
        case OPT_IMAGERY_RESOLUTION:
            if (!tp_imagery_cli_parse_resolution("build", "--imagery-resolution", optarg,
                                                 &o->imagery_cli))
                return TP_EXIT_USAGE;
            break;
        case OPT_THREADS:
            if (!tp_parse_int(optarg, 1, 1024, &o->build.threads))
                return tp_option_error("build", "--threads", "1 .. 1024", optarg), TP_EXIT_USAGE;
            break;
        case OPT_JSON: o->json = optarg; break;
        case OPT_QUIET: o->build.quiet = 1; break;
        case OPT_ALLOW_GAPS: o->build.allow_gaps = 1; break;
        case OPT_Z_UNIT:
            if (strcmp(optarg, "m") && strcmp(optarg, "ft") && strcmp(optarg, "us-ft"))
                return tp_option_error("build", "--z-unit", "m, ft or us-ft", optarg),
                       TP_EXIT_USAGE;
            o->build.z_unit = optarg;
            break;
        case 'h': print_help(); return tp_cli_finish(TP_EXIT_OK);
        case ':': return tp_cli_usage_at("build", "missing value for option", argv[optind - 1]);
        default:
            if (optopt > 0 && optopt < 256) {
                char name[3] = {'-', (char)optopt, '\0'};
                return tp_cli_usage_at("build", "unknown option", name);
            }
            if (optopt >= 256)
                return tp_cli_usage_at("build", "option takes no value:", argv[optind - 1]);
            return tp_cli_usage_at("build", "unknown option", argv[optind - 1]);
        }
    }
    if (optind >= argc)
        return tp_cli_usage_at("build", "missing SOURCE", "");
    if (!o->build.out)
        return tp_cli_usage_at("build", "missing -o NAME.tpt", "");
    if (o->imagery_shift_given && o->imagery_cli.resolution_m > 0)
        return tp_cli_usage_at("build", "give --imagery-texel-shift or --imagery-resolution, not both", "");
    if ((o->imagery_shift_given || o->imagery_cli.resolution_m > 0) && !o->imagery_count)
        return tp_cli_usage_at("build", "--imagery-texel-shift and --imagery-resolution need --imagery", "");
    o->build.sources = (const char**)(argv + optind);
    o->build.source_count = argc - optind;
    if (o->build.threads == 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        o->build.threads = n > 0 ? (int)(n > 1024 ? 1024 : n) : 1;
    }
    return -1;
}
