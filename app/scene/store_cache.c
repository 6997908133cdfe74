/* store_cache.c - DEMs built into stores once, reused next time (see store_cache.h). */
#define _DEFAULT_SOURCE
#include "store_cache.h"
#include "store_build.h"

#include "cli.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

void tp_store_cache_dir(const char* cache_dir, char* out, size_t cap)
{
    const char* env;
    if (cache_dir && cache_dir[0])
        snprintf(out, cap, "%s", cache_dir);
    else if ((env = getenv("TP_CACHE_DIR")) && env[0])
        snprintf(out, cap, "%s", env);
    else if ((env = getenv("XDG_CACHE_HOME")) && env[0])
        snprintf(out, cap, "%s/terrapatch", env);
    else if ((env = getenv("HOME")) && env[0])
        snprintf(out, cap, "%s/.cache/terrapatch", env);
    else
        snprintf(out, cap, ".terrapatch-cache");
}

/* mkdir -p; 1 when dir exists and is writable afterwards. */
static int make_dirs(const char* dir)
{
    char p[PATH_MAX];
    if (snprintf(p, sizeof p, "%s", dir) >= (int)sizeof p)
        return 0;
    for (char* s = p + 1; *s; s++)
        if (*s == '/') {
            *s = '\0';
            if (mkdir(p, 0755) != 0 && errno != EEXIST)
                return 0;
            *s = '/';
        }
    if (mkdir(p, 0755) != 0 && errno != EEXIST)
        return 0;
    return access(p, W_OK | X_OK) == 0;
}

static uint64_t fnv(uint64_t h, const void* data, size_t n)
{
    const unsigned char* p = data;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

static uint64_t fnv_str(uint64_t h, const char* s)
{
    return fnv(h, s ? s : "", (s ? strlen(s) : 0) + 1);
}

/* The lock of one cached store's build: an flock on STORE.lock (beside it, empty, removed when
 * the build ends), held until the descriptor is closed or the process ends, however it ends. Waits,
 * saying so once, while another process holds it. -1 when no lock can be had (a build without one).
 */
static int lock_build(const char* store)
{
    char lock[PATH_MAX];
    if (snprintf(lock, sizeof lock, "%s.lock", store) >= (int)sizeof lock)
        return -1;
    int said = 0;
    /* the file locked must still be the one at the path: a build that ended removed it, and the
     * next builder locks the file that is there now (so two never build at once) */
    for (int tries = 0; tries < 1000; tries++) {
        int fd = open(lock, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0)
            return -1;
        if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
            if (errno != EWOULDBLOCK) {
                close(fd);
                return -1;
            }
            if (!said++)
                tp_cli_note("another terrapatch is building %s: waiting for it", store);
            int r;
            while ((r = flock(fd, LOCK_EX)) != 0 && errno == EINTR)
                ;
            if (r != 0) {
                close(fd);
                return -1;
            }
        }
        struct stat held, now;
        if (fstat(fd, &held) == 0 && stat(lock, &now) == 0 && held.st_ino == now.st_ino &&
            held.st_dev == now.st_dev)
            return fd;
        close(fd);
    }
    return -1;
}

/* Ends a build: its lock file goes while it is held (a process still waiting on it takes the
 * lock, sees the file gone and locks the one at the path, if any), then the lock. */
static void unlock_build(const char* store, int fd)
{
    char lock[PATH_MAX];
    if (snprintf(lock, sizeof lock, "%s.lock", store) < (int)sizeof lock)
        unlink(lock);
    close(fd);
}

/* Removes the temporary files of builds that died in dir (kill -9, a power cut: no handler ran):
 * NAME.tpt.tmpXXXXXXXX (atomic_write's names) whose NAME.tpt.lock no live build holds. One
 * line says how many and how many bytes. */
static void sweep(const char* dir)
{
    DIR* d = opendir(dir);
    if (!d)
        return;
    int swept = 0;
    long long bytes = 0;
    for (struct dirent* e; (e = readdir(d));) {
        const char* tmp = strstr(e->d_name, ".tpt.tmp");
        if (!tmp || strlen(tmp + 8) != 8)
            continue;
        char path[PATH_MAX], lock[PATH_MAX];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path ||
            snprintf(lock, sizeof lock, "%s/%.*s.lock", dir, (int)(tmp + 4 - e->d_name),
                     e->d_name) >= (int)sizeof lock)
            continue;
        /* no lock file: its build ended (a live one keeps it); else its lock must be free */
        int fd = open(lock, O_RDWR | O_CLOEXEC);
        if (fd < 0 && errno != ENOENT)
            continue;
        struct stat sb;
        if ((fd < 0 || flock(fd, LOCK_EX | LOCK_NB) == 0) && lstat(path, &sb) == 0 &&
            S_ISREG(sb.st_mode) && unlink(path) == 0) {
            swept++;
            bytes += sb.st_size;
        }
        if (fd >= 0)
            close(fd);
    }
    closedir(d);
    if (swept)
        tp_cli_note("removed %d temporary file%s (%.1f MB) that a killed build "
                    "left in %s",
                    swept, swept == 1 ? "" : "s", bytes / 1e6, dir);
}

/* 1 when path opens as a store built from abs_path with the given patch size. */
static int store_matches(const char* path, const char* abs_path, int patch_size)
{
    tp_store* st = NULL;
    tp_error err;
    if (access(path, R_OK) != 0 || tp_store_open(path, &st, &err) != TP_OK)
        return 0;
    tp_store_info in;
    tp_store_get_info(st, &in);
    char want[PATH_MAX + 16];
    snprintf(want, sizeof want, "source: %s\n", abs_path);
    int ok = in.header.notes && strstr(in.header.notes, want) &&
             (1 << in.header.geometry.n) + 1 == patch_size;
    tp_store_close(st);
    return ok;
}

void tp_store_cache_remove_temporary(const char* path)
{
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%s", path);
    char* slash = strrchr(dir, '/');
    unlink(path);
    if (slash) {
        *slash = '\0';
        rmdir(dir);
    }
}

int tp_store_cache_get(const char* dem, const tp_store_cache_options* o, char* out, size_t cap,
                       int* temporary_out)
{
    *temporary_out = 0;
    /* the DEM's identity: its absolute path (a virtual path's archive made absolute), size
     * and time */
    char abs_path[PATH_MAX];
    tp_input_identity id;
    tp_error err;
    if (tp_input_check(dem, "a raster", 1, &err) != TP_OK ||
        tp_input_identify(dem, abs_path, sizeof abs_path, &id, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv_str(h, "terrapatch store cache 2"); /* 2: the height step from the grid's values */
    h = fnv_str(h, abs_path);
    int64_t meta[3] = {id.size_bytes, id.mtime_ns, o->patch_size};
    h = fnv(h, meta, sizeof meta);
    h = fnv_str(h, o->crs);
    h = fnv(h, &o->resampling, sizeof o->resampling);
    h = fnv_str(h, o->z_unit);
    const int fill_max = o->fill_max_px == 0  ? TP_FILL_MAX_ANY
                         : o->fill_max_px < 0 ? 0
                                              : o->fill_max_px;
    h = fnv(h, &fill_max, sizeof fill_max);
    char from_path[PATH_MAX] = "";
    if (o->fill_from && *o->fill_from) {
        /* the second source's identity: a changed file makes a new store */
        tp_input_identity fid;
        if (tp_input_check(o->fill_from, "a raster", 1, &err) != TP_OK ||
            tp_input_identify(o->fill_from, from_path, sizeof from_path, &fid, &err) != TP_OK) {
            tp_cli_error("--fill-from %s", err.message);
            return TP_EXIT_FAILURE;
        }
        int64_t fmeta[2] = {fid.size_bytes, fid.mtime_ns};
        h = fnv_str(h, "fill-from");
        h = fnv_str(h, from_path);
        h = fnv(h, fmeta, sizeof fmeta);
    }

    char dir[PATH_MAX];
    tp_store_cache_dir(o->cache_dir, dir, sizeof dir);
    int temporary = 0;
    if (!make_dirs(dir)) {
        const char* tmp = getenv("TMPDIR");
        char tdir[PATH_MAX];
        snprintf(tdir, sizeof tdir, "%s/terrapatch-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!mkdtemp(tdir)) {
            tp_cli_error("cannot write the store cache %s nor a temporary "
                         "directory %s: %s",
                         dir, tdir, strerror(errno));
            return TP_EXIT_FAILURE;
        }
        tp_cli_note("the cache directory %s is not writable: building in %s "
                    "instead (removed after the view; choose one with --cache-dir)",
                    dir, tdir);
        snprintf(dir, sizeof dir, "%s", tdir);
        temporary = 1;
    }
    const char* base = strrchr(abs_path, '/');
    base = base ? base + 1 : abs_path;
    char name[256];
    snprintf(name, sizeof name, "%.200s", base);
    char* dot = strrchr(name, '.');
    if (dot && dot != name)
        *dot = '\0';
    if (snprintf(out, cap, "%s/%s-%016llx.tpt", dir, name, (unsigned long long)h) >= (int)cap) {
        tp_cli_error("%s: the cache path is too long", dir);
        return TP_EXIT_FAILURE;
    }
    if (!temporary && store_matches(out, abs_path, o->patch_size)) {
        sweep(dir);
        return TP_EXIT_OK;
    }
    /* one build of this store at a time: a second process waits, then finds it built */
    if (!temporary)
        sweep(dir);
    int lock_fd = temporary ? -1 : lock_build(out);
    if (lock_fd >= 0 && store_matches(out, abs_path, o->patch_size)) {
        close(lock_fd); /* releases the lock */
        return TP_EXIT_OK;
    }

    tp_cli_note("building a store of %s in %s (once; reused next time)", dem, dir);
    tp_build_options bo;
    tp_build_options_init(&bo);
    const char* sources[1] = {abs_path};
    bo.sources = sources;
    bo.source_count = 1;
    bo.out = out;
    bo.patch_size = o->patch_size;
    bo.fill_max = fill_max;
    bo.fill_from = from_path[0] ? from_path : NULL;
    bo.crs = o->crs;
    bo.z_unit = o->z_unit;
    if (o->resampling == TP_RESAMPLING_CUBIC)
        bo.resampling = TP_RESAMPLING_CUBIC;
    int code = tp_store_build(&bo, NULL);
    fflush(stdout);
    if (lock_fd >= 0)
        unlock_build(out, lock_fd);
    if (temporary && code != TP_EXIT_OK)
        rmdir(dir);
    *temporary_out = temporary && code == TP_EXIT_OK;
    return code;
}

int tp_store_cache_heightmap(const char* image, const tp_image_options* io, const char* cache_dir,
                             char* out, size_t cap)
{
    char abs_path[PATH_MAX];
    tp_input_identity id;
    tp_error err;
    if (tp_input_check(image, "an image", 0, &err) != TP_OK ||
        tp_input_identify(image, abs_path, sizeof abs_path, &id, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    /* the image's identity and what places it: another spacing or origin is another DEM */
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv_str(h, "terrapatch placed heightmap 1");
    h = fnv_str(h, abs_path);
    int64_t meta[2] = {id.size_bytes, id.mtime_ns};
    h = fnv(h, meta, sizeof meta);
    double place[5] = {io->spacing_m, io->zscale, (double)io->has_origin,
                       io->has_origin ? io->origin_lat_deg : 0,
                       io->has_origin ? io->origin_lon_deg : 0};
    h = fnv(h, place, sizeof place);
    char dir[PATH_MAX];
    tp_store_cache_dir(cache_dir, dir, sizeof dir);
    if (!make_dirs(dir)) {
        tp_cli_error("%s: cannot write the store cache %s: %s (choose one with --cache-dir)", image,
                     dir, strerror(errno));
        return TP_EXIT_FAILURE;
    }
    const char* base = strrchr(abs_path, '/');
    base = base ? base + 1 : abs_path;
    int n = snprintf(out, cap, "%s/%.*s-%016llx.placed.tif", dir,
                     (int)(strrchr(base, '.') ? strrchr(base, '.') - base : (long)strlen(base)),
                     base, (unsigned long long)h);
    if (n < 0 || (size_t)n >= cap) {
        tp_cli_error("%s: the cache path is too long", image);
        return TP_EXIT_FAILURE;
    }
    if (access(out, F_OK) == 0)
        return TP_EXIT_OK; /* placed before with the same options */
    tp_dem* d = NULL;
    tp_status rs = tp_dem_read_image(image, io, &d, &err);
    if (rs != TP_OK) {
        tp_cli_error("%s", err.message);
        return rs == TP_ERR_INVALID_ARG ? TP_EXIT_USAGE : TP_EXIT_FAILURE;
    }
    tp_cli_note("placing %s (%dx%d samples at %g m posts) in %s as a GeoTIFF (once; reused next "
                "time)",
                image, d->width, d->height, fabs(d->geotransform[1]), out);
    tp_status s = tp_dem_write_geotiff(d, out, &err);
    tp_dem_destroy(d);
    if (s != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}
