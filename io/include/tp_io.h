/*
 * tp_io.h - terrapatch input/output behind plain C: DEM rasters (GDAL), heightmap and RGBA
 * images (OpenImageIO), CRS descriptions (GDAL's OGR), the metric render grid (GDAL, PROJ),
 * textures draped on it, triangle meshes for ParaView (VTK), and the georeference between grid,
 * render CRS and WGS84 (PROJ, GeographicLib). Conversions between geographic, UTM/UPS, MGRS and
 * other WGS84 coordinates are in tp_geo.h.
 *
 * C11 header; the C++17 implementation lives in io/src, and no GDAL, PROJ, VTK, OpenImageIO or
 * GeographicLib type appears here.
 *
 * Errors: every function that returns a tp_status checks its arguments (a NULL pointer not
 * documented as allowed is TP_ERR_INVALID_ARG), catches every C++ exception inside it
 * (std::bad_alloc becomes TP_ERR_OUT_OF_MEMORY, any other exception TP_ERR_BACKEND with the
 * exception's message, unless the function says otherwise), and leaves its out-parameters
 * untouched on failure; with an err, the message says what went wrong. The functions that
 * return anything else (the _destroy functions, which accept NULL; the _terrain_desc copies;
 * tp_is_heightmap_image; the tp_georef accessors and grid <-> CRS arithmetic) call nothing that
 * throws, and take valid pointers unless they say otherwise.
 */
#ifndef TP_IO_H
#define TP_IO_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Band 1 of a raster, as read: the transient input to tp_terrain_create. */
typedef struct tp_dem {
    int width, height;
    float* heights;          /* width * height, row-major, row 0 first; NaN = nodata */
    double geotransform[6];  /* GDAL geotransform (pixel-is-point already turned into corners) */
    int has_geotransform;    /* 0 if the file had none (then (0,1,0,0,0,-1) is filled in) */
    char* crs_wkt;           /* WKT2 of the CRS, or "" if the file has none; owned */
    int epsg;                /* EPSG code of the CRS when known, else 0 */
    char driver[32];         /* GDAL driver short name: "GTiff", "SRTMHGT", "AAIGrid", ... */
    char data_type[16];      /* GDAL data type of band 1: "Int16", "Float32", ... */
    int is_integer_type;     /* 1 for integer band types */
    int has_nodata;          /* 1 if the band has a nodata tag */
    double nodata_value;     /* the tag's value when has_nodata */
    size_t void_count;       /* samples that are nodata (tag, NaN, or untagged -32768/-32767) */
    double min_m, max_m;     /* over valid samples; NaN if none */
    char units[32];          /* band unit type as the file states it ("metre", "ft", "") */
    /* Heights are in metres: read in z_unit and multiplied by z_to_m (1 for metres and for an
     * unknown unit, which is taken as metres with a warning). z_unit: "metre", "international
     * foot", "US survey foot", "" when the file states none; z_unit_from: how it is known
     * ("band unit 'ft'", "vertical CRS 'NAVD88 height (ftUS)'", "--z-unit ft"), "" when not. */
    double z_to_m;
    char z_unit[48];
    char z_unit_from[200];
    char vertical_datum[160]; /* the vertical CRS's name, as the file states it; "" when none */
    /* Warnings worth showing the user (one per line, '\n'-separated), e.g. untagged Int16
     * -32768/-32767 taken as nodata. "" when none. Owned. */
    char* warnings;
} tp_dem;

/* The georeference a DEM may have. Outside these ranges a geotransform is damage (a pixel of
 * 1e-300 m, an extent of 1e300 m), not a place on the Earth: tp_dem_read refuses it, saying
 * which value is outside which range. Pixel sizes in metres apply to projected CRSs (in their
 * own linear unit converted to metres), those in degrees to geographic ones; a DEM without a CRS
 * may have either (its units are unknown). Corner coordinates: projected within
 * +-TP_COORD_MAX_M, geographic longitudes within +-TP_LON_MAX_DEG (a grid in 0 .. 360 may reach
 * past 360: 355 .. 365 is a place) spanning at most 360 degrees plus one wrap-around column
 * (latitudes: sample centres within +-90). */
#define TP_PIXEL_SIZE_MIN_M 1e-3
#define TP_PIXEL_SIZE_MAX_M 1e6
#define TP_PIXEL_SIZE_MIN_DEG 1e-8
#define TP_PIXEL_SIZE_MAX_DEG 10.0
#define TP_COORD_MAX_M 1e8
#define TP_LON_MAX_DEG 540.0

/* Reads band 1 of any raster GDAL opens. Int16 rasters without a nodata tag have -32768 and
 * -32767 taken as nodata, with a warning; +-Inf and +-FLT_MAX heights are nodata too (with a
 * warning). Also warned about: a .prj beside the file that GDAL cannot read as a CRS, and a
 * raster with neither CRS nor geotransform (taken as 1 m posts). DTED checksums are verified
 * (GDAL's DTED_VERIFY_CHECKSUM, unless the environment sets it), and ESRI ASCII grids get a
 * pass over their text (GDAL reads "307x" as 307 and ignores values past nrows x ncols).
 * Errors name the file and what was wrong; on failure *out is untouched:
 *   TP_ERR_IO             missing file, a directory GDAL cannot open, a FIFO, device or socket
 *                         (refused before opening: reading one could block forever);
 *   TP_ERR_BAD_DATA       empty or unreadable files, non-finite, rotated or zero-size
 *                         geotransforms, gt[1] < 0, pixel sizes or corners outside the ranges
 *                         above, geographic rows beyond +-90 degrees, a read that fails part
 *                         way, a DTED column whose checksum does not match, an ASCII grid with
 *                         a token that is not a number or more or fewer values than nrows x
 *                         ncols (the message gives the line), no valid sample;
 *   TP_ERR_OUT_OF_MEMORY  heights that would not fit in this machine's memory (refused before
 *                         allocating; the message says how much they would need);
 *   TP_ERR_INVALID_ARG    a NULL or empty path, a NULL out. */
tp_status tp_dem_read(const char* path, tp_dem** out, tp_error* err);
/* tp_dem_read with the unit of the heights given (--z-unit: "m", "ft" or "us-ft"), overriding
 * what the file says; NULL: the file's (band 1's unit type, else its vertical CRS's unit).
 * TP_ERR_INVALID_ARG for another z_unit. */
tp_status tp_dem_read_z(const char* path, const char* z_unit, tp_dem** out, tp_error* err);
void tp_dem_destroy(tp_dem* dem); /* accepts NULL */

/* What a DEM file states about its heights' datum (io/src/vertical_datum.cpp). Heights are
 * never converted; this only reports. */
typedef struct tp_vertical_info {
    char datum[160]; /* the name of the file's vertical CRS ("EGM96 height", "NAVD88 height"),
                        "" when the file states none (then the datum is unknown to us) */
    char units[32];  /* band 1's unit type ("metre", "m", "" when unknown) */
    char driver[32]; /* GDAL driver short name ("SRTMHGT", "GTiff", ...) */
} tp_vertical_info;

/* Opens path with GDAL (no heights read) and writes what its CRS says of the vertical datum.
 * TP_ERR_IO for a missing file or one that is not regular (a FIFO would block),
 * TP_ERR_BAD_DATA for one GDAL cannot open; *out written only on success. */
tp_status tp_dem_vertical_info(const char* path, tp_vertical_info* out, tp_error* err);

/* A tp_terrain_desc pointing into dem (valid while dem lives), with the given patch size/fit.
 * dem NULL gives a desc without heights, which tp_terrain_create refuses. */
tp_terrain_desc tp_dem_terrain_desc(const tp_dem* dem, int patch_size, tp_fit fit);

/* ---------------------------------------------------------------------------------------------
 * Inputs (io/src/input_file.cpp): how every command checks a path it is about to read, and
 * names it for the store cache.
 */

/* Refuses, in one line naming path, an input that is not a regular file before anything opens
 * it: a FIFO (opening it waits for a writer, forever if none comes), a character or block
 * device (/dev/zero never ends), a socket, a missing path, and a directory unless
 * allow_directory (a raster can be one: an ArcInfo binary grid). `what` is what the file
 * should have been ("a route file (GPX, GeoJSON, KML, CSV)"). A GDAL virtual path (/vsizip/,
 * /vsigzip/, /vsitar/, /vsicurl/, ...) is asked of GDAL's virtual file system (VSIStatL): one
 * it cannot find is "PATH: cannot open: no such file (GDAL virtual path)"; the local archive
 * such a path reads (/vsizip/DIR/a.zip/...) must be a regular file. TP_ERR_IO with a message
 * starting with the path; TP_OK otherwise. */
tp_status tp_input_check(const char* path, const char* what, int allow_directory, tp_error* err);

/* 1 when path is a GDAL virtual path ("/vsi" followed by a handler name and '/'). */
int tp_input_is_virtual(const char* path);

/* What names an input file for a cache: its absolute path (a relative path made absolute, as
 * realpath does; in a virtual path, the archive's path after /vsizip/, /vsigzip/, /vsitar/,
 * /vsi7z/ or /vsirar/ made absolute, so that the name reads the same file from any folder),
 * its size and its modification time (ns since the epoch; for a member of a local archive, the
 * archive's time, and its size mixed into the member's).
 * Call tp_input_check first: this only names. TP_ERR_IO naming path when it cannot be found;
 * TP_ERR_INVALID_ARG when the absolute path does not fit cap bytes. */
typedef struct tp_input_identity {
    int64_t size_bytes;
    int64_t mtime_ns;
} tp_input_identity;
tp_status tp_input_identify(const char* path, char* abs_path, size_t cap, tp_input_identity* out,
                            tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Coordinate reference systems (io/src/crs.cpp, through GDAL's OGR)
 */
typedef struct tp_crs_info {
    char name[160]; /* the CRS's own name, e.g. "NAD83 / UTM zone 10N"; "" when it has none */
    int epsg;       /* its EPSG code, or the one GDAL recognises (AutoIdentifyEPSG); else 0 */
    int geographic; /* 1 for a geographic CRS (latitude and longitude), 0 otherwise */
    int utm_zone;   /* 1..60 for a UTM zone (any datum: "NAD83 / UTM zone 10N" too), 0
                       (TP_ZONE_UPS) for UPS, -1 otherwise (and for no CRS) */
    int northp;     /* the hemisphere of utm_zone */
} tp_crs_info;

/* Describes a CRS given as GDAL/PROJ read it: WKT (a tp_dem's crs_wkt), "EPSG:N", a PROJ
 * string. "" means no CRS: TP_OK with every field zero but utm_zone (-1). TP_ERR_BAD_DATA for text
 * GDAL cannot read as a CRS; *out is untouched on failure. */
tp_status tp_crs_describe(const char* crs, tp_crs_info* out, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Files written whole or not at all (io/src/atomic_write.cpp)
 *
 * Every file terrapatch writes (images, meshes, JSON, CSV) goes through this writer. The bytes
 * go to a new temporary file beside path, named path + ".tmp" + 8 random characters and created
 * with O_CREAT | O_EXCL | O_NOFOLLOW (a file or symlink planted there is never opened, let
 * alone followed); every write() is checked (ENOSPC, EFBIG, EDQUOT, EIO end the write, EINTR
 * is retried); commit checks the size on disk, fsyncs, closes (checked), renames over path and
 * fsyncs the folder. On any failure, and on SIGINT/SIGTERM once tp_interrupt_install has run,
 * the temporary file is removed and path is left exactly as it was: the old file, or none.
 * Messages name path: "PATH: cannot write: No space left on device", "PATH: interrupted
 * (SIGTERM): not written".
 */
typedef struct tp_file_writer tp_file_writer;

/* Creates the temporary file. TP_ERR_INVALID_ARG for a name ending in '/', TP_ERR_IO when the
 * folder does not exist or is not writable (or after a signal). */
tp_status tp_file_begin(const char* path, tp_file_writer** out, tp_error* err);
/* Appends size bytes, in pieces of at most 4 MiB with the signal flag checked between them.
 * On failure the temporary file is already gone; w must still be aborted (or committed, which
 * returns the same failure). */
tp_status tp_file_append(tp_file_writer* w, const void* data, size_t size, tp_error* err);
/* Overwrites size bytes at offset of what was appended already (offset + size <= the bytes
 * appended so far; else TP_ERR_INVALID_ARG): for a header whose values are known only at the
 * end. Fails as tp_file_append does. */
tp_status tp_file_rewrite(tp_file_writer* w, uint64_t offset, const void* data, size_t size,
                          tp_error* err);
/* Makes the file path: fsync, close, rename, fsync of the folder. Frees w, whatever happens. */
tp_status tp_file_commit(tp_file_writer* w, tp_error* err);
/* Removes the temporary file and frees w; path is untouched. Accepts NULL. */
void tp_file_abort(tp_file_writer* w);
/* begin, append, commit: the whole of data as the file path. */
tp_status tp_file_write(const char* path, const void* data, size_t size, tp_error* err);

/* Several files written all or none (io/src/file_set.cpp): a command's outputs (a JSON, a
 * CSV and a plot; a raster and its sidecars). Each file added is written whole to its own
 * temporary file beside its path at once (as tp_file_write: every write checked, size checked,
 * fsync, close); nothing is renamed until the commit. The commit looks at the signal flag a
 * last time, then with SIGINT/SIGTERM blocked moves every older file aside (a hard link, so
 * the path never goes missing) and renames every temporary file over its path; if a rename
 * fails, the ones done are undone (the older files put back, new names removed). Any failure
 * before or during the commit leaves every path as it was: the older files, or none. The set
 * holds interruption (tp_interrupt_hold) from begin to commit or abort. */
typedef struct tp_file_set tp_file_set;

/* An empty set. TP_ERR_OUT_OF_MEMORY; *out written only on success. */
tp_status tp_file_set_begin(tp_file_set** out, tp_error* err);
/* Writes data (size bytes) to a new temporary file for path. TP_ERR_INVALID_ARG for a path
 * already in the set or ending in '/'; TP_ERR_IO as tp_file_write (full disk, missing folder,
 * signal), after which every later call and the commit fail the same way (abort s). */
tp_status tp_file_set_add(tp_file_set* s, const char* path, const void* data, size_t size,
                          tp_error* err);
/* Removes path, if it exists, with the commit (and puts it back if the commit fails): a stale
 * sidecar of an older output that the new one does not have. */
tp_status tp_file_set_remove(tp_file_set* s, const char* path, tp_error* err);
/* Puts every file of the set in place, all or none. Frees s, whatever happens. The message
 * names the path that failed. */
tp_status tp_file_set_commit(tp_file_set* s, tp_error* err);
/* Removes the temporary files and frees s; every path is untouched. Accepts NULL. */
void tp_file_set_abort(tp_file_set* s);

/* Checks, before long work that ends by writing path, that it can be written: its folder
 * exists and is writable and path is not a folder. Writes nothing. TP_ERR_IO (or
 * TP_ERR_INVALID_ARG for "" or a name ending in '/') with a message naming path. */
tp_status tp_output_check(const char* path, tp_error* err);

/* SIGINT and SIGTERM. tp_interrupt_install sets handlers (not for a signal the program started
 * with ignored, as nohup and background jobs do) that only record the signal while a temporary
 * file or folder of the writers is live; at any other moment they restore the default action
 * and re-raise it, so the program dies as it would without them (nothing of ours is on disk).
 * Once recorded, the writers remove their temporaries and fail; tp_interrupted() returns the
 * signal (0 if none), and the program should exit with status 128 + that signal. (A signal
 * after a writer's last look, during the rename, lets that file complete; it is still
 * recorded.)
 * tp_interrupt_hold/release bracket other work that checks tp_interrupted() itself (nested
 * holds count; the writers hold while a temporary lives). Main thread only. */
void tp_interrupt_install(void);
int tp_interrupted(void);
void tp_interrupt_hold(void);
void tp_interrupt_release(void);
/* After the program's last output is in place: SIGINT and SIGTERM are ignored from now on and a
 * signal recorded since the writers' last look is forgotten (tp_interrupted() returns 0), so the
 * program ends as having written its outputs (its "wrote" lines, status 0), never 130/143 with
 * them in place. Call it while holding (tp_interrupt_hold) across the last commit, so that no
 * signal kills the program between the rename and this call. */
void tp_interrupt_finished(void);

/* ---------------------------------------------------------------------------------------------
 * Heightmap images without georeference (io/src/image_read.cpp, through OpenImageIO)
 */
/* The ranges of tp_image_options' spacing_m and zscale (besides 0, the default), and the
 * heights the scaled counts may reach (either sign): beyond them tp_dem_read_image refuses the
 * options with TP_ERR_INVALID_ARG. */
#define TP_IMAGE_SPACING_MIN_M TP_PIXEL_SIZE_MIN_M
#define TP_IMAGE_SPACING_MAX_M TP_PIXEL_SIZE_MAX_M
#define TP_IMAGE_ZSCALE_MIN 1e-6
#define TP_IMAGE_ZSCALE_MAX 1e5
#define TP_IMAGE_HEIGHT_MAX_M 1e5

typedef struct tp_image_options {
    double spacing_m;        /* post spacing, TP_IMAGE_SPACING_MIN_M .. _MAX_M; 0 means 1 m
                                (with a warning) */
    double zscale;           /* metres per count of channel 0, TP_IMAGE_ZSCALE_MIN .. _MAX; 0
                                means 1 */
    int has_origin;          /* place the image's centre at (origin_lat, origin_lon) in the */
    double origin_lat_deg;   /* WGS84 UTM/UPS zone of that point; otherwise the grid is in */
    double origin_lon_deg;   /* local metres with its north-west corner at (0, 0) */
} tp_image_options;

/* 1 when path names an image format read through OpenImageIO rather than GDAL (by extension:
 * .png .jpg .jpeg .exr .pgm .ppm .tga .bmp .hdr .webp). */
int tp_is_heightmap_image(const char* path);

/* Reads channel 0 of an image (8/16/32-bit integer or float samples, taken as raw counts, not
 * normalised) as heights = count * zscale. North-up: row 0 is north. Only for rasters without
 * georeference: a file that is not a heightmap image by extension and that GDAL reads with a
 * CRS or a geotransform (a GeoTIFF, an .hgt) is refused with TP_ERR_INVALID_ARG ("FILE is
 * georeferenced (CRS ...); --spacing/--zscale apply only to ..."); read it with tp_dem_read.
 * So are spacing_m and zscale outside their ranges, and heights beyond +-TP_IMAGE_HEIGHT_MAX_M
 * after scaling. Before decoding: a path that is not a regular file is TP_ERR_IO; a PNG whose
 * chunks are cut short or fail their CRC, or whose header claims more pixels than its
 * compressed data can hold, TP_ERR_BAD_DATA; an image that would not fit in memory,
 * TP_ERR_OUT_OF_MEMORY. The codecs' own messages (libpng's "libpng error: ...") are kept off
 * stderr: their text is in err. Errors name the file; *out is untouched on failure. */
tp_status tp_dem_read_image(const char* path, const tp_image_options* options, tp_dem** out,
                            tp_error* err);

/* Writes d as a Float32 GeoTIFF (DEFLATE, tiled; NaN nodata; band unit "metre"; its
 * geotransform and CRS) at path, through a temporary file beside it renamed when complete:
 * a heightmap image placed with tp_image_options, made a DEM GDAL reads, so that a store can
 * be built from it (the store cache, app/store_cache.c). TP_ERR_IO naming path on failure. */
tp_status tp_dem_write_geotiff(const tp_dem* d, const char* path, tp_error* err);

/* Writes an RGBA8 image (w x h, top row first) to path through OpenImageIO, the format from the
 * extension (.png, .jpg, .tif, ...). The image is encoded in memory and written with
 * tp_file_write: a failure (full disk, signal) leaves nothing behind and an older file as it
 * was. TP_ERR_INVALID_ARG for an extension OpenImageIO cannot encode in memory. */
tp_status tp_image_write_rgba(const char* path, int w, int h, const uint8_t* rgba, tp_error* err);
/* tp_output_check, and that path's extension names a format tp_image_write_rgba can write: for
 * a screenshot path, before the rendering. Writes nothing. */
tp_status tp_image_output_check(const char* path, tp_error* err);

/* Reads an image as RGBA8 (w x h, top row first; grey and RGB are expanded, alpha 255).
 * *rgba is malloc'd: free() it. */
tp_status tp_image_read_rgba(const char* path, int* w, int* h, uint8_t** rgba, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * The render grid: a DEM on a metric grid (io/src/render_grid.cpp)
 *
 * Projected DEMs in metres are used on their own grid. Geographic DEMs (and projected ones in
 * other units) are warped with GDAL to the WGS84 UTM zone of the DEM's centre (UPS north of 84N
 * or south of 80S): one zone for the whole scene, bilinear (or cubic) resampling, square posts
 * at the finest source spacing found at the extent's corners and centre (so the source is
 * never undersampled), source nodata passed as NaN. A DEM without a CRS (and no options->crs)
 * whose geotransform is plainly geographic (north-up, cells under 0.1, every edge within +-180
 * / +-90: an ASCII grid in degrees without its .prj) is taken as EPSG:4326; any other as
 * metres. Both with a warning.
 *
 * Voids. Nodata is classified on the render grid into connected regions (4-neighbour): a
 * region that touches the grid's border (its first or last row or column) is outside the data (a
 * collar, a warp's wedges) and is never filled; a region that does not is an interior void,
 * filled whatever its size unless fill_max_px caps it (bounding box at most fill_max_px samples
 * wide and high), and marked as filled. Each void is filled on its own crop, its bounding box
 * grown on every side by its reach (the box's longer side + 1): by GDALFillNodata
 * (inverse-distance interpolation from the valid samples around it, search distance the reach, no
 * smoothing), or, with fill_from, from that second source (any GDAL raster, any CRS and
 * resolution, warped bilinearly onto the render grid) shifted onto the surrounding ground: delta
 * = DEM - OTHER on the valid samples around the void is interpolated across it as above, and
 * the void gets OTHER + delta (no step at its rim); where OTHER has no data the void's samples
 * are interpolated. Outside voids and capped ones stay NaN: never drawn, never fabricated.
 */
typedef enum tp_resampling {
    TP_RESAMPLING_DEFAULT = 0, /* = bilinear */
    TP_RESAMPLING_BILINEAR,
    TP_RESAMPLING_CUBIC
} tp_resampling;

typedef struct tp_grid_options {
    const char* crs;        /* overrides the DEM's CRS ("EPSG:4326", WKT, ...); NULL: the file's */
    tp_resampling resampling;
    int fill_max_px;        /* 0: any size; > 0: voids up to N x N samples; negative: none */
    /* Fill voids from this raster (--fill-from), shifted onto the DEM (above); NULL or "":
     * interpolate. Errors name the file: TP_ERR_IO (missing), TP_ERR_BAD_DATA (not a raster,
     * no georeference or CRS, no overlap with the DEM or no data over it). */
    const char* fill_from;
} tp_grid_options;

typedef struct tp_render_grid {
    int width, height;
    float* heights;          /* width * height; NaN = not drawn */
    uint8_t* filled;         /* width * height; 1 = interior void filled (see "Voids") */
    double geotransform[6];  /* render CRS */
    char* crs_wkt;           /* render CRS as WKT2; "" for local metres (no CRS). Owned */
    int epsg;                /* of the render CRS when known, else 0 */
    char crs_name[160];      /* "WGS 84 / UTM zone 31N", or "local metres (no CRS)" */
    int utm_zone;            /* 1..60 when the render CRS is a UTM zone, 0 for UPS, -1 otherwise */
    int northp;              /* hemisphere of utm_zone */
    int wgs84;               /* 1 if the render CRS's datum is WGS84 (GeographicLib applies exactly) */
    int warped;              /* 1 if resampled from the DEM's own CRS */
    double warp_max_error_m, warp_rms_error_m; /* warp: rendered surface vs the source posts */
    size_t warp_posts;       /* source posts the warp error was measured at */
    double spacing_m;        /* |geotransform[1]| when square, else the smaller spacing */
    size_t filled_samples;   /* interior voids filled */
    size_t large_void_samples, outside_samples; /* not drawn */
    char* warnings;          /* '\n'-separated lines for the user, "" when none. Owned */
    size_t filled_from_samples; /* of filled_samples, those from options->fill_from */
} tp_render_grid;

/* Builds the render grid of a DEM. A warped grid keeps only samples inside the hull of the
 * source posts (GDAL's output reaches half a post further, where it would only repeat the edge).
 * Errors: TP_ERR_INVALID_ARG for an unknown options->crs or geographic posts beyond +-90
 * degrees; TP_ERR_BAD_DATA for an unreadable dem->crs_wkt or a DEM one UTM/UPS zone cannot
 * hold (see tp_render_grid_plan); TP_ERR_BACKEND when GDAL or PROJ
 * fails. *out is untouched on failure. */
tp_status tp_render_grid_build(const tp_dem* dem, const tp_grid_options* options,
                               tp_render_grid** out, tp_error* err);
void tp_render_grid_destroy(tp_render_grid* grid); /* accepts NULL */

/* The width and height tp_render_grid_build would give dem with these options, without warping
 * (cheap: the warp is planned from the DEM's edges), for checking memory before building. Fails
 * as tp_render_grid_build does for a DEM no zone can hold (below).
 *
 * Warps are bounded by the source: a geographic DEM whose posts the zone of its centre would
 * scale by more than 5% (UTM keeps within 0.1%: a DEM many zones wide, or one reaching from a
 * pole far into UTM latitudes) is TP_ERR_BAD_DATA, with a message naming the extent and a CRS to
 * reproject to first; and a warp whose finest post spacing would give more than 4x the source's
 * samples (posts converging near a pole, very anisotropic cells) uses posts as many as the
 * source's over the warped extent instead, with a warning saying so. */
tp_status tp_render_grid_plan(const tp_dem* dem, const tp_grid_options* options, int* width,
                              int* height, tp_error* err);

/* A tp_terrain_desc pointing into grid (valid while grid lives); grid NULL as for
 * tp_dem_terrain_desc. */
tp_terrain_desc tp_render_grid_terrain_desc(const tp_render_grid* grid, int patch_size,
                                            tp_fit fit);

/* ---------------------------------------------------------------------------------------------
 * Mosaics read in bands (io/src/mosaic.cpp): any number of sources as one render grid, for
 * grids larger than memory (terrapatch build)
 *
 * Sources GDAL opens (tiles of any format mix, a .vrt) become one terrain through GDAL's VRT
 * machinery: sources that share CRS and post spacing are mosaicked with GDALBuildVRT; sources
 * of different CRSs or spacings are each warped (GDALWarp to a VRT) onto one grid and those are
 * mosaicked. Where sources overlap, the later one wins (as GDAL's VRT does); gaps are nodata.
 * The render grid is chosen as tp_render_grid_build chooses it for one DEM (the UTM/UPS zone of
 * the centre for geographic sources, the sources' own projected CRS in metres, options->crs
 * overriding the sources' CRS; the finest post spacing among the sources; north-up, square
 * posts), and one DEM gives the same grid and, sample for sample, the same heights as
 * tp_dem_read + tp_render_grid_build with the same fill_max (voids filled in windows of rows:
 * see tp_mosaic_options.fill_max).
 * Nothing is read whole: tp_mosaic_read_rows reads a window of rows through GDAL's block cache
 * (sized from options->memory_mb), so memory follows the window, not the grid.
 */
typedef struct tp_mosaic tp_mosaic;

typedef struct tp_mosaic_options {
    const char* crs;          /* as tp_grid_options.crs: overrides every source's CRS */
    tp_resampling resampling; /* for warps */
    int memory_mb;            /* budget of the whole process; GDAL's block cache gets a quarter.
                                 0 means 1024 */
    /* Voids filled as tp_render_grid_build fills them (the same regions, crops and
     * GDALFillNodata, so the same heights), read in bands: largest void side filled, in
     * samples; TP_FILL_MAX_ANY: any size; 0 (or less) fills nothing (unlike tp_grid_options,
     * 0 is not "any"). The window of rows read grows until it holds whole, with its crop, every
     * void reaching the rows asked for; a void whose crop (its rows and its reach, the bounding
     * box's longer side + 1, above and below) is taller than fill_window_mb holds at about 60
     * bytes a sample of a row stays a void (tp_mosaic_get_voids counts it). The per-sample
     * "filled" marks come with tp_mosaic_read_rows_filled. */
    int fill_max;
    const char* fill_from;    /* as tp_grid_options.fill_from (warped VRT, read in bands) */
    const char* z_unit;       /* the sources' height unit ("m", "ft", "us-ft"), overriding
                                 theirs; NULL: each source's (as tp_dem_read_z), which must
                                 agree. Heights are read in metres */
    int fill_window_mb;       /* memory for the void window; 0: memory_mb / 8, taken from GDAL's
                                 block cache (which then gets an eighth, not a quarter) */
} tp_mosaic_options;

#define TP_FILL_MAX_ANY 0x7fffffff /* tp_mosaic_options.fill_max: voids of any size */

typedef struct tp_mosaic_info {
    int width, height;          /* the render grid */
    double geotransform[6];     /* render CRS */
    const char* crs_wkt;        /* render CRS as WKT2; "" for local metres. Owned by the mosaic */
    char crs_name[160];
    int epsg;                   /* of the render CRS when known, else 0 */
    double spacing_m;           /* post spacing of the render grid */
    int source_count;
    int warped;                 /* 1 if any source is resampled onto the grid */
    int integer_sources;        /* 1 if every source's band 1 has an integer type */
    /* The share of the grid's extent that some source covers: the union of the sources'
     * footprints on a 1024 x 1024 raster over the extent (overlaps count once), 0 .. 1; 1 for
     * one source. The rest is gaps, nodata (terrapatch build refuses under a half without
     * --allow-gaps). */
    double covered_share;
    /* A bound of the grid's heights known without reading the grid: statistics every source
     * carries (exact ones, as GDAL writes them; resampling bilinear only, cubic overshoots), or,
     * for a grid read without resampling from files holding at most half its samples (a VRT
     * repeating a few small files), those files' exact min/max (read at open). 1 and the range,
     * else 0. A VRT that scales its sources can exceed it: check what is read. */
    int has_range;
    double min_m, max_m;
    /* What was decided, one line each ('\n'-separated): the sources, warps, CRS and spacing
     * differences, overlaps ("A and B overlap by one row (SRTM tiles share their edge); GDAL's
     * VRT takes the later one"), gaps, nodata guesses. Owned by the mosaic. */
    const char* notes;
} tp_mosaic_info;

/* Opens the sources (paths[0 .. path_count-1], path_count >= 1) and plans the grid; reads no
 * heights. Each source is checked as tp_dem_read checks a DEM before reading it (a FIFO or
 * device refused before opening, georeference within its ranges, DTED checksums verified on
 * read, an ASCII grid's text) and the errors name the file: TP_ERR_IO (missing, not a regular
 * file), TP_ERR_BAD_DATA (not a raster, bad georeference; with several sources, one without a
 * geotransform), TP_ERR_INVALID_ARG (an unknown options->crs), TP_ERR_BACKEND (GDAL fails to
 * mosaic or warp). */
tp_status tp_mosaic_open(const char* const* paths, size_t path_count,
                         const tp_mosaic_options* options, tp_mosaic** out, tp_error* err);
void tp_mosaic_close(tp_mosaic* m); /* accepts NULL */
void tp_mosaic_get_info(const tp_mosaic* m, tp_mosaic_info* out);

/* Reads rows y0 .. y0+rows-1 (within the grid) of the render grid into heights (rows * width
 * floats, row-major; height_count >= that): metres, NaN where nothing is drawn (nodata, gaps,
 * outside the warped sources; untagged Int16 -32768/-32767 and +-Inf/+-FLT_MAX as tp_dem_read).
 * Not thread-safe for one mosaic. TP_ERR_BAD_DATA (naming the source when GDAL says which) when
 * a read fails part way, e.g. a truncated tile or a DTED checksum mismatch. */
tp_status tp_mosaic_read_rows(tp_mosaic* m, int y0, int rows, float* heights, size_t height_count,
                              tp_error* err);
/* Samples filled so far (options->fill_max) in the rows above the furthest row read: each row
 * counted once, so reading the grid down, once or more, counts each filled sample once. */
size_t tp_mosaic_filled_samples(const tp_mosaic* m);
/* tp_mosaic_read_rows that also writes, for each sample read, 1 where it is a filled void
 * sample (options->fill_max), else 0 (filled: rows * width bytes; NULL: as tp_mosaic_read_rows).
 * The same samples tp_render_grid_build's `filled` marks for one DEM. */
tp_status tp_mosaic_read_rows_filled(tp_mosaic* m, int y0, int rows, float* heights,
                                     size_t height_count, uint8_t* filled, tp_error* err);

/* What became of the voids in the rows read so far (each row counted once, as above). */
typedef struct tp_mosaic_voids {
    size_t filled_samples;      /* = tp_mosaic_filled_samples */
    size_t filled_from_samples; /* of those, from options->fill_from */
    size_t too_large_samples;   /* interior voids within fill_max left because their crop is
                                   taller than max_void_rows */
    int max_void_rows;          /* the tallest crop the window may hold; 0 when not filling */
} tp_mosaic_voids;
void tp_mosaic_get_voids(const tp_mosaic* m, tp_mosaic_voids* out); /* m NULL: all 0 */

/* ---------------------------------------------------------------------------------------------
 * Textures draped on the render grid (io/src/texture.cpp)
 *
 * A georeferenced image (an orthophoto GeoTIFF, any CRS) is warped by GDAL onto the render
 * grid's CRS and extent, so that texel (i, j) of the result covers the grid's pixel area: the
 * sample (x, y) sits at texture coordinates ((x + 0.5) / grid width, (y + 0.5) / grid height).
 * An image without georeference (a PNG, read through OpenImageIO) is taken to cover the same
 * extent. The result is RGBA8, top row first, at most max_size texels per side (aspect kept
 * by scaling both sides alike); texels outside the image are transparent (alpha 0).
 * Colour comes from the bands GDAL labels red, green and blue, wherever they are, else from the
 * first three bands (an RGB + near-infrared orthophoto shows as RGB), else from one grey band;
 * a palette band is expanded through its colour table. Alpha comes only from a band GDAL labels
 * alpha (so a 4th band is not taken for alpha unless it says so). A raster without bands is
 * TP_ERR_BAD_DATA.
 */
typedef struct tp_texture {
    int width, height;
    uint8_t* rgba;     /* width * height * 4; owned */
    int georeferenced; /* 1 if warped from the image's own georeference */
} tp_texture;

/* Errors name the file: TP_ERR_INVALID_ARG for max_size < 1, TP_ERR_IO for a file that cannot
 * be opened or read (and, before opening, a path that is not a regular file: a FIFO would
 * block), TP_ERR_BAD_DATA for a PNG cut short, failing a CRC or claiming more pixels than its
 * data holds, TP_ERR_OUT_OF_MEMORY for an image whose pixels would not fit in memory (from its
 * header, before decoding), TP_ERR_BACKEND when GDAL or OpenImageIO fails. The codecs' own
 * stderr lines are kept off stderr; their text is in err. */
tp_status tp_texture_build(const char* path, const tp_render_grid* grid, int max_size,
                           tp_texture** out, tp_error* err);
void tp_texture_destroy(tp_texture* tex); /* accepts NULL */

/* ---------------------------------------------------------------------------------------------
 * Triangle meshes for ParaView (io/src/vtk_mesh_write.cpp and vtk_mesh_inspect.cpp, VTK's own writers and readers)
 */
typedef struct tp_mesh {
    size_t point_count;
    const double* xyz;          /* 3 per point: E, N (render CRS, or minus origin), elevation m */
    const double* elevation_m;  /* per point: point data "elevation_m" */
    const uint8_t* void_filled; /* per point: point data "void_filled" (0/1) */
    size_t triangle_count;
    const uint64_t* triangles;  /* 3 point indices per triangle, counter-clockwise from above */
    const int32_t* patch_id;    /* per triangle: cell data "patch_id" */
    const uint8_t* lod;         /* per triangle: cell data "lod" (k = n is full resolution) */
    const double* max_error_m;  /* per triangle: cell data "max_error_m" */
    /* Field data (strings may be NULL or ""): */
    const char* crs_wkt;
    int epsg;
    const char* utm_zone; /* e.g. "31n", "UPS n" (tp_zone_format, TP_ZONE_STYLE_SHORT) */
    const char* source_file;
    const char* camera;         /* the camera as a --camera-geo / --camera string */
    const char* lod_params;     /* e.g. "mode=error tau_px=1" */
    const char* program_version;
    double origin[3];           /* subtracted from every point (0 unless --origin local) */
    const char* void_filled_note; /* field data "void_filled_note" (NULL or "": none), e.g.
                                     why void_filled is not known (a store's export) */
} tp_mesh;

typedef enum tp_mesh_format {
    TP_MESH_DEFAULT = 0, /* from the extension: .vtp, .vtk or .vtm */
    TP_MESH_VTP,         /* VTK XML PolyData, binary, compressed */
    TP_MESH_VTK,         /* legacy VTK, binary */
    TP_MESH_VTM          /* VTK XML multiblock, one PolyData block per patch */
} tp_mesh_format;

/* Checks point_count and triangle_count against the limits of format (TP_MESH_DEFAULT: of every
 * format), without allocating: every format numbers points and the 3 point ids of each
 * triangle with VTK's vtkIdType, 64-bit in Debian's VTK 9.1, so a mesh may hold up to
 * 2^63 - 1 points and (2^63 - 2) / 3 triangles. (Legacy .vtk files are written as version 4.2,
 * 32-bit, when the mesh fits and as 5.1, 64-bit, when not; .vtm pieces are single patches.)
 * TP_ERR_INVALID_ARG with a message naming the count and the limit; TP_OK otherwise. */
tp_status tp_mesh_check_size(tp_mesh_format format, size_t point_count, size_t triangle_count,
                             tp_error* err);

/* Writes the mesh with VTK's writers: points as doubles, triangles as cells (not strips), the
 * point, cell and field data above (field data also holds "triangle_count"). Atomic: .vtp and
 * .vtk go through tp_file_write; a .vtm's index and pieces are built in a new temporary folder
 * of an unpredictable name beside path and renamed into place. On any failure (unwritable
 * directory, full disk, bad extension, counts beyond tp_mesh_check_size's limits, SIGINT or
 * SIGTERM after tp_interrupt_install: tp_interrupted() then says which) nothing is left behind,
 * older files stay as they were, and the message names the path. */
tp_status tp_mesh_write(const char* path, tp_mesh_format format, const tp_mesh* mesh,
                        tp_error* err);

/* Fills mesh (already holding the field data given to tp_mesh_write_pieces) with piece number
 * piece (0 .. piece_count - 1, asked for in order): its points and triangles, indices local to
 * the piece, and the same point and cell data arrays in every piece (non-NULL pointers, also
 * when a piece is empty). The arrays stay the caller's and must live until the next call or
 * the end of tp_mesh_write_pieces. Returns TP_OK, or a failure with err set: the write stops
 * and nothing is left behind. */
typedef tp_status (*tp_mesh_piece_fn)(void* user, size_t piece, tp_mesh* mesh, tp_error* err);

/* Writes a .vtp of piece_count pieces (VTK's XML PolyData pieces, appended raw data,
 * compressed), asking piece_fn for each in turn and writing it before asking for the next:
 * memory follows the largest piece, not the mesh, so a mesh of any size streams to disk. The
 * pieces are independent PolyData in one file, read by VTK and ParaView as one dataset; points
 * where pieces meet are repeated (ParaView's Clean filter merges them). fields gives the field
 * data (its arrays are ignored); "triangle_count" is triangle_total. Each piece holds fewer
 * than 2^31 points and triangles. Atomic as tp_mesh_write (a temporary file beside path,
 * renamed when complete; on a failure, a full disk or a signal nothing is left and an older
 * file stays). TP_ERR_INVALID_ARG for a path not ending in .vtp, a piece's index out of range
 * or a piece too large. */
tp_status tp_mesh_write_pieces(const char* path, const tp_mesh* fields, size_t triangle_total,
                               size_t piece_count, tp_mesh_piece_fn piece_fn, void* user,
                               tp_error* err);

/* What a mesh file holds, read back with VTK's readers (tests, --check). */
typedef struct tp_mesh_summary {
    size_t points, triangles, other_cells;
    int points_are_double;
    int has_elevation, has_void_filled, has_patch_id, has_lod, has_max_error;
    int has_crs, has_source, has_version; /* field data present */
    size_t boundary_loops;   /* connected loops of boundary edges (vtkFeatureEdges) */
    size_t boundary_edges, non_manifold_edges;
    double max_error_m;      /* largest cell max_error_m */
    double bounds[6];        /* xmin, xmax, ymin, ymax, zmin, zmax */
    size_t blocks;           /* .vtm: number of blocks; else 1 */
    size_t pieces;           /* .vtp: its pieces (tp_mesh_write_pieces; 1 for tp_mesh_write).
                                With several, the points where they meet are merged (as a .vtm's
                                blocks are) before the edges are counted, and points and
                                void_filled_points count the merged surface's points */
    size_t void_filled_points; /* points whose void_filled is not 0 */
    size_t downward_triangles; /* triangles not counter-clockwise seen from above (E, N) */
} tp_mesh_summary;

tp_status tp_mesh_inspect(const char* path, tp_mesh_summary* out, tp_error* err);

/* The points of a .vtp or .vtk mesh (3 doubles each, in file order), read back with VTK's
 * readers (tests comparing two meshes point for point). *xyz is allocated with malloc (the
 * caller frees it); *xyz and *count are written only on success. TP_ERR_INVALID_ARG for
 * another extension, TP_ERR_IO, TP_ERR_BAD_DATA as tp_mesh_inspect. */
tp_status tp_mesh_read_points(const char* path, double** xyz, size_t* count, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Georeference (io/src/georef.cpp): grid (x, y) <-> render CRS (E, N) <-> WGS84 (lat, lon).
 *
 * Grid coordinates are (column, row) with sample centres at integers, as GDAL's geotransform
 * defines them (pixel-is-point rasters already have a corner-based geotransform from GDAL, so
 * nothing is shifted twice): E = gt[0] + (x + 0.5) gt[1], N = gt[3] + (y + 0.5) gt[5].
 * When the render CRS is a WGS84 UTM zone or UPS, (E, N) <-> (lat, lon) is GeographicLib's
 * UTMUPS (exact to nanometres), in the scene's zone even outside its standard area. Any other
 * CRS goes through PROJ to WGS84; tp_georef_datum_accuracy_m says how accurate that step is.
 * Heights are never converted: they stay as in the DEM (orthometric for SRTM: EGM96).
 */
typedef struct tp_georef tp_georef;

/* crs_wkt "" or NULL: local metres (no geographic position). TP_ERR_BAD_DATA for unreadable
 * WKT, TP_ERR_BACKEND when PROJ has no operation to WGS84. The conversion functions below
 * write their outputs only on success. */
tp_status tp_georef_create(const char* crs_wkt, const double geotransform[6], tp_georef** out,
                           tp_error* err);
void tp_georef_destroy(tp_georef* g); /* accepts NULL */

/* 1 if positions can be turned into latitude and longitude. */
int tp_georef_has_geo(const tp_georef* g);

void tp_georef_grid_to_proj(const tp_georef* g, double x, double y, double* e_m, double* n_m);
void tp_georef_proj_to_grid(const tp_georef* g, double e_m, double n_m, double* x, double* y);

/* Render CRS (E, N) <-> WGS84 latitude, longitude (degrees; longitude in [-180, 180]).
 * TP_ERR_INVALID_ARG when there is no CRS, for coordinates that are not finite (or a latitude
 * beyond +-90), and when the point cannot be converted (outside the range of GeographicLib's
 * UTMUPS, for instance: its message is kept). */
tp_status tp_georef_proj_to_geo(const tp_georef* g, double e_m, double n_m, double* lat_deg,
                                double* lon_deg, tp_error* err);
tp_status tp_georef_geo_to_proj(const tp_georef* g, double lat_deg, double lon_deg, double* e_m,
                                double* n_m, tp_error* err);

/* Accuracy (metres) of the render CRS -> WGS84 step: 0 when exact (WGS84 itself), PROJ's stated
 * accuracy of the operation it uses, or -1 when PROJ gives none (a ballpark datum shift used
 * because the datum grids are missing: expect errors of a metre or more). */
double tp_georef_datum_accuracy_m(const tp_georef* g);
/* One line describing that step, e.g. "exact (WGS 84)" or the PROJ operation's name; owned by g,
 * valid while g lives. */
const char* tp_georef_datum_note(const tp_georef* g);

/* ---------------------------------------------------------------------------------------------
 * Terrain stores (.tpt): a built tp_tree on disk (io/src/store_*.cpp; format in docs/store.md)
 *
 * A versioned little-endian file: a header (geometry, georeference, quantisation, CRS, the
 * sources it was built from), the node table (every node's tp_node_meta, laid out as in memory so
 * that it is mapped, not decoded), the location table (the offset, size, CRC32 and codec of every
 * node's data) and each node's samples, compressed (and, from format 3, the cell mask of the
 * nodes above the leaves that are drawn in part; from format 4, the filled bits of the nodes
 * holding filled void samples). Written atomically through tp_file_* (an
 * interrupted or failed write leaves no file); read with one open file shared by threads
 * (pread), each node checked against its CRC32 when read. Formats 2 and 3 are written and read
 * on little-endian hosts only (TP_ERR_BACKEND elsewhere).
 */
#define TP_STORE_VERSION 4 /* 4: filled bits of the nodes holding filled void samples */

typedef struct tp_store_header {
    tp_tree_geometry geometry;
    double geotransform[6];    /* of the fitted grid, render CRS */
    double height_step_m;
    double quant_max_error_m;
    double err_unit_steps;
    size_t valid_samples, nodata_samples; /* of the source grid (padding not counted) */
    const char* crs_wkt;       /* render CRS as WKT; "" for none */
    const char* notes;         /* free text: sources, mosaic and warp decisions ('\n'-separated) */
} tp_store_header;

typedef struct tp_store_writer tp_store_writer;
/* Starts writing path (tp_file_begin) and writes the header. TP_ERR_INVALID_ARG for a geometry
 * that is not the one of (n, src_width, src_height) (the message names the field), a CRS or notes
 * over 16 MiB; TP_ERR_IO; each with a message naming path. *out written only on success. The
 * writer writes each node's table entries into place as the node is added and keeps one bit per
 * node in memory, never the tables or the data. */
tp_status tp_store_writer_begin(const char* path, const tp_store_header* header,
                                tp_store_writer** out, tp_error* err);
/* Adds one node (any order; each node exactly once): its meta, its (2^n+1)^2 global
 * quantised heights (INT32_MIN = not drawn), which the writer stores relative to meta->qmin,
 * compressed, and its cell mask (tp_node_mask_words(n) words, as the tree builder emits it;
 * stored only for a node of scale >= 1 drawn in part, may be NULL for others), appended to the
 * file at once. TP_ERR_INVALID_ARG (nothing written, w still usable) for a node that does not
 * exist or was added already, unknown flags, a missing mask, a drawn height outside meta's
 * qmin..qmax or a range wider than 65534 steps; TP_ERR_IO when the write fails
 * (then every later call and the commit fail the same way: abort w). */
tp_status tp_store_writer_add_node(tp_store_writer* w, int64_t node, const tp_node_meta* meta,
                                   const int32_t* q, const uint16_t* mask, tp_error* err);
/* tp_store_writer_add_node with the node's filled bits (tp_node_filled_words(n) words, as the
 * tree builder's emit_filled gives them): required when meta has TP_NODE_HAS_FILLED, NULL
 * otherwise; stored compressed after the node's samples and mask (docs/store.md, format 4).
 * TP_ERR_INVALID_ARG also for bits missing or given against the flag, a bit on a sample not
 * drawn or past the samples, or the flag with no bit set. */
tp_status tp_store_writer_add_node_filled(tp_store_writer* w, int64_t node,
                                          const tp_node_meta* meta, const int32_t* q,
                                          const uint16_t* mask, const uint16_t* filled,
                                          tp_error* err);
/* The header's values known only once the whole grid has been read (a build that reads its
 * sources once): they replace the header's quant_max_error_m, valid_samples and nodata_samples
 * given to tp_store_writer_begin; commit writes the header again with them (tp_file_rewrite of
 * the same bytes with those three fields and its CRC32 changed; the format is unchanged). Any
 * time before commit; the last call wins. */
void tp_store_writer_set_totals(tp_store_writer* w, double quant_max_error_m,
                                size_t valid_samples, size_t nodata_samples);
/* Replaces the header's notes by notes of the same length in bytes (for counts known only at
 * the end: the begin's notes reserve room, e.g. with trailing spaces); commit writes them.
 * TP_ERR_INVALID_ARG when the length differs (w is unchanged). */
tp_status tp_store_writer_set_notes(tp_store_writer* w, const char* notes, tp_error* err);
/* Checksums the tables (read back), writes the footer and makes the file (tp_file_commit). Frees w, whatever
 * happens. TP_ERR_INVALID_ARG when a node is missing (the message says how many and the first),
 * TP_ERR_IO; on failure no file is left and an older path is as it was. */
tp_status tp_store_writer_commit(tp_store_writer* w, tp_error* err);
void tp_store_writer_abort(tp_store_writer* w); /* accepts NULL; leaves no file */

typedef struct tp_store tp_store;
typedef struct tp_store_info {
    tp_store_header header;    /* strings owned by the store */
    uint32_t version;
    uint64_t file_bytes, data_bytes, table_bytes;
    double bytes_per_sample;   /* file_bytes / (src_width * src_height) */
} tp_store_info;

/* Opens a store: checks magic ("not a terrapatch store"), the header's checksum, the version (a
 * newer one: "written by a newer terrapatch (format N; this one reads up to M)"; an older one:
 * "written by an older terrapatch (format N; ...): rebuild it with terrapatch build"), the
 * geometry against the one n and the source size define, the footer's and both tables'
 * checksums, every meta's flags and range, and that every node's data lies inside the file (one
 * pass of pread over the tables, 128 bytes per node). Then maps the tables read-only: the store
 * takes a few KB of the process's own memory whatever its node count (the mapped pages are the
 * file's, shared with the page cache). Do not truncate an open store (a mapping past the end of
 * its file is SIGBUS) nor rewrite it in place (the metas would change under the tree; node reads
 * check their location's bounds again); terrapatch itself always writes a new file and renames
 * it. TP_ERR_BAD_DATA (damaged, truncated, an older or newer format, not a store) / TP_ERR_IO
 * (cannot read or map; a FIFO, device or folder) / TP_ERR_BACKEND (a big-endian host) with a
 * message naming path; *out written only on success. */
tp_status tp_store_open(const char* path, tp_store** out, tp_error* err);
void tp_store_close(tp_store* s); /* accepts NULL */
void tp_store_get_info(const tp_store* s, tp_store_info* out);
/* Every node's meta (node_count of them, in id order; delta[k > n], eps[][kn >= n] and pad_
 * are 0), owned by s and valid while s is open: a read-only mapping of the file's node table. */
const tp_node_meta* tp_store_metas(const tp_store* s, size_t* count);
/* Reads, checks (CRC32) and decodes node's samples into samples ((2^n+1)^2 uint16 relative to
 * its qmin, TP_TREE_NO_HEIGHT where not drawn; sample_capacity at least that; node in
 * 0..node_count-1). With sample_capacity >= tp_tree_block_words(n), the node's cell mask
 * follows the samples (stored, or made from its samples or flags): a block for tp_tree_attach. Thread-safe: any number of threads may read one open store at once (pread;
 * each thread keeps its own zstd context and buffers for its lifetime). About 15 us for a
 * 65x65 node (docs/store.md). TP_ERR_BAD_DATA for a checksum or decoding failure, a sample
 * outside the node's range or a cell mask that marks a cell with an undrawn corner whole, TP_ERR_IO for a read failure, each with a message naming the file,
 * the node ("node 38 (scale 0, column 3, row 4)") and its byte offset; samples are written
 * only on success. */
tp_status tp_store_read_node(const tp_store* s, int64_t node, uint16_t* samples,
                             size_t sample_capacity, tp_error* err);
/* The tree of an open store (tp_tree_create with the header's geometry, geotransform, height
 * step, quantisation error and error unit, and the store's metas): no node resident yet; attach
 * blocks read with tp_store_read_node. The tree borrows the store's metas: destroy it before
 * closing s. Fails as tp_tree_create (TP_ERR_OUT_OF_MEMORY; tp_store_open has checked the rest);
 * *out written only on success. */
tp_status tp_tree_create_from_store(const tp_store* s, tp_tree** out, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Viewsheds through GDAL (io/src/viewshed_gdal.cpp)
 *
 * The core computes viewsheds itself (tp_viewshed_compute); these are for comparing with GDAL
 * and for saving the result.
 */

/* GDAL's own viewshed (GDALViewshedGenerate, the library form of gdal_viewshed, mode GVM_Edge
 * as gdal_viewshed's default, values 255 / 0 / 0 outside the radius) of the same in-memory grid
 * and observer, with tp_viewshed_compute's arguments, into out (out_count >= width * height; the
 * samples outside GDAL's window are 0). The grid goes to GDAL as a Float32 MEM dataset (NaN =
 * nodata) whose CRS is a sphere of options->earth_radius_m (GDAL takes the curvature's earth
 * from the CRS's semi-major axis), and the observer as its sample's centre. Fails as
 * tp_viewshed_compute does for the observer (outside the grid: TP_ERR_INVALID_ARG; on nodata:
 * TP_ERR_BAD_DATA, checked here since GDAL would spread the NaN); TP_ERR_BACKEND when GDAL
 * fails. out is untouched on failure. */
tp_status tp_gdal_viewshed(const float* heights, size_t height_count, int width, int height,
                           const double geotransform[6], int observer_x, int observer_y,
                           const tp_viewshed_options* options, uint8_t* out, size_t out_count,
                           tp_error* err);

/* Writes a viewshed as tp_byte_raster_write does (below), in the format path's extension names,
 * band description "visibility: 255 seen, 0 not seen or beyond the radius". No nodata tag: 0 is
 * "not seen". */
tp_status tp_viewshed_write(const char* path, const uint8_t* values, size_t value_count, int width,
                            int height, const double geotransform[6], const char* crs_wkt,
                            tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Output formats (io/src/output_format.cpp): the one place that decides, from an output path's
 * extension (case ignored), the format it is written in, for every writer below that follows
 * the extension (tp_byte_raster_write, tp_contours_write in tp_vector.h, tp_image_write_rgba)
 * and for the commands, which check their outputs with it before any work.
 */
typedef enum tp_output_kind {
    TP_OUTPUT_NONE = 0,
    TP_OUTPUT_BYTE_RASTER, /* one band of bytes on a georeference (viewshed, light): GeoTIFF
                              (.tif, .tiff), PNG (.png; a .wld world file and an .aux.xml with
                              the CRS beside), GeoPackage (.gpkg), lossless JPEG 2000 (.jp2,
                              .j2k), Erdas Imagine (.img), Arc/Info ASCII Grid (.asc; a .prj
                              beside), BMP (.bmp; .wld, .aux.xml): those this GDAL has */
    TP_OUTPUT_VECTOR,      /* lines with fields (contours): any OGR format that creates vector
                              files, by its extension (.gpkg, .shp, .geojson, .kml, ...) */
    TP_OUTPUT_STORE,       /* a terrain store (build): .tpt */
    TP_OUTPUT_PLOT,        /* a plot gnuplot draws (los --profile, profile --png): .png */
    TP_OUTPUT_IMAGERY,     /* an imagery pyramid (imagery -o): .tpi */
    TP_OUTPUT_LIGHT_MAP,   /* a day's light map (light --day -o): .tpl */
    TP_OUTPUT_MESH,        /* a triangle mesh (export -o), through VTK's writers: VTK XML
                              PolyData (.vtp), legacy VTK (.vtk), VTK XML multiblock (.vtm) */
    TP_OUTPUT_SCREENSHOT,  /* an RGBA picture (view --screenshot), through OpenImageIO's writer
                              for the extension, encoded in memory (tp_image_write_rgba): PNG
                              (.png), TIFF (.tif, .tiff), JPEG (.jpg, .jpeg), BMP (.bmp), Targa
                              (.tga), WebP (.webp), OpenEXR (.exr) */
} tp_output_kind;

typedef struct tp_output_format {
    char driver[32]; /* the writer: the GDAL driver's short name ("GTiff", "PNG", "GPKG"),
                        OpenImageIO's format name for a screenshot ("png", "tiff"); "" for a
                        store, a plot or a mesh */
    char name[64];   /* the format as the lists name it ("GeoTIFF", "PNG", "terrapatch store") */
    tp_mesh_format mesh; /* TP_OUTPUT_MESH: the VTK file written; TP_MESH_VTP otherwise */
} tp_output_format;

/* The format path is written in as an output of kind. TP_ERR_INVALID_ARG with a message
 * "PATH: why" when there is none: no extension, an unknown one, a raster format that is lossy
 * ("JPEG is lossy: ...") or that is not among those above; *out written only on success. */
tp_status tp_output_format_for(const char* path, tp_output_kind kind, tp_output_format* out,
                               tp_error* err);

/* What kind is written in, for messages: "GeoTIFF (.tif, .tiff), PNG (.png), ..." into buf (at
 * most cap bytes with the NUL; cut short when cap is too small; buf may be NULL with cap 0).
 * Returns the length of the whole list, as snprintf. */
size_t tp_output_formats(tp_output_kind kind, char* buf, size_t cap);

/* ---------------------------------------------------------------------------------------------
 * Byte rasters (io/src/byte_raster.cpp): the viewshed's and the light map's outputs
 */

/* Writes values (width * height bytes = value_count, row 0 first) as a one-band Byte raster in
 * the format path's extension names (tp_output_format_for, TP_OUTPUT_BYTE_RASTER) with
 * geotransform and crs_wkt ("" or NULL: none), e.g. a render grid's, and the band description
 * description (NULL or "": none). GDAL's driver encodes it in memory (CreateCopy from a MEM
 * dataset; a GeoTIFF DEFLATE-compressed and tiled), with the sidecars the driver writes (a PNG's
 * .wld world file, GDAL's .aux.xml holding the CRS and description where the format cannot),
 * and the files are written all or none (tp_file_set_*): an older file and its sidecars stay as
 * they were on failure; older sidecars GDAL would read with the new file (PATH.aux.xml, world
 * files PATH's stem .wld, .XXw for .XYZ) that the new one lacks are removed with it. No nodata
 * tag. TP_ERR_INVALID_ARG for NULL values or path, a size mismatch, a path whose format is not
 * written (tp_output_format_for's message), a bad path (as tp_file_begin); TP_ERR_BAD_DATA for a
 * crs_wkt GDAL cannot read; TP_ERR_IO when writing fails; TP_ERR_BACKEND when GDAL does. */
tp_status tp_byte_raster_write(const char* path, const uint8_t* values, size_t value_count,
                               int width, int height, const double geotransform[6],
                               const char* crs_wkt, const char* description, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_H */
