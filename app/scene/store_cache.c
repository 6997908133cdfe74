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
#include <pthread.h>
#include <stdatomic.h>
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
 * NAME.tpt.tmpXXXXXXXX (atomic_write's names), and previews NAME.preview.tpt with theirs, whose
 * NAME.tpt.lock no live build holds. One line says how many and how many bytes. */
static void sweep(const char* dir)
{
    DIR* d = opendir(dir);
    if (!d)
        return;
    int swept = 0;
    long long bytes = 0;
    for (struct dirent* e; (e = readdir(d));) {
        /* NAME.tpt.tmpXXXXXXXX, and a preview's NAME.preview.tpt and its temporary files, all
         * under NAME.tpt.lock */
        const char* tmp = strstr(e->d_name, ".tpt.tmp");
        const size_t len = strlen(e->d_name);
        const int preview = len > 12 && !strcmp(e->d_name + len - 12, ".preview.tpt");
        if (!preview && (!tmp || strlen(tmp + 8) != 8))
            continue;
        const char* end = preview ? e->d_name + len - 4 : tmp; /* ".tpt" */
        int stem = (int)(end - e->d_name);
        if (stem > 8 && !strncmp(end - 8, ".preview", 8))
            stem -= 8;
        char path[PATH_MAX], lock[PATH_MAX];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path ||
            snprintf(lock, sizeof lock, "%s/%.*s.tpt.lock", dir, stem, e->d_name) >=
                (int)sizeof lock)
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

/* One cached store being looked up or built: the DEM's identity and the cache's folder. */
typedef struct cache_entry {
    char abs_path[PATH_MAX];  /* the DEM's */
    char from_path[PATH_MAX]; /* --fill-from's, or "" */
    char dir[PATH_MAX];
    int fill_max;
    int temporary; /* dir is a temporary folder of this process's */
    int lock_fd;   /* the build's lock, or -1 */
} cache_entry;

/* Finds dem's store (its path into out): TP_EXIT_OK with *found set when the cache holds it;
 * with *found 0, the build's lock is held (e->lock_fd, unless the folder is temporary) and the
 * store is to be built. Else an exit code after one line. */
static int entry_open(const char* dem, const tp_store_cache_options* o, char* out, size_t cap,
                      cache_entry* e, int* found)
{
    *found = 0;
    e->lock_fd = -1;
    e->temporary = 0;
    /* the DEM's identity: its absolute path (a virtual path's archive made absolute), size
     * and time */
    tp_input_identity id;
    tp_error err;
    if (tp_input_check(dem, "a raster", 1, &err) != TP_OK ||
        tp_input_identify(dem, e->abs_path, sizeof e->abs_path, &id, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv_str(h, "terrapatch store cache 2"); /* 2: the height step from the grid's values */
    h = fnv_str(h, e->abs_path);
    int64_t meta[3] = {id.size_bytes, id.mtime_ns, o->patch_size};
    h = fnv(h, meta, sizeof meta);
    h = fnv_str(h, o->crs);
    h = fnv(h, &o->resampling, sizeof o->resampling);
    h = fnv_str(h, o->z_unit);
    e->fill_max = o->fill_max_px == 0  ? TP_FILL_MAX_ANY
                  : o->fill_max_px < 0 ? 0
                                       : o->fill_max_px;
    h = fnv(h, &e->fill_max, sizeof e->fill_max);
    e->from_path[0] = '\0';
    if (o->fill_from && *o->fill_from) {
        /* the second source's identity: a changed file makes a new store */
        tp_input_identity fid;
        if (tp_input_check(o->fill_from, "a raster", 1, &err) != TP_OK ||
            tp_input_identify(o->fill_from, e->from_path, sizeof e->from_path, &fid, &err) !=
                TP_OK) {
            tp_cli_error("--fill-from %s", err.message);
            return TP_EXIT_FAILURE;
        }
        int64_t fmeta[2] = {fid.size_bytes, fid.mtime_ns};
        h = fnv_str(h, "fill-from");
        h = fnv_str(h, e->from_path);
        h = fnv(h, fmeta, sizeof fmeta);
    }

    tp_store_cache_dir(o->cache_dir, e->dir, sizeof e->dir);
    if (!make_dirs(e->dir)) {
        const char* tmp = getenv("TMPDIR");
        char tdir[PATH_MAX];
        snprintf(tdir, sizeof tdir, "%s/terrapatch-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
        if (!mkdtemp(tdir)) {
            tp_cli_error("cannot write the store cache %s nor a temporary "
                         "directory %s: %s",
                         e->dir, tdir, strerror(errno));
            return TP_EXIT_FAILURE;
        }
        tp_cli_note("the cache directory %s is not writable: building in %s "
                    "instead (removed after the view; choose one with --cache-dir)",
                    e->dir, tdir);
        snprintf(e->dir, sizeof e->dir, "%s", tdir);
        e->temporary = 1;
    }
    const char* base = strrchr(e->abs_path, '/');
    base = base ? base + 1 : e->abs_path;
    char name[256];
    snprintf(name, sizeof name, "%.200s", base);
    char* dot = strrchr(name, '.');
    if (dot && dot != name)
        *dot = '\0';
    if (snprintf(out, cap, "%s/%s-%016llx.tpt", e->dir, name, (unsigned long long)h) >= (int)cap) {
        tp_cli_error("%s: the cache path is too long", e->dir);
        return TP_EXIT_FAILURE;
    }
    if (!e->temporary && store_matches(out, e->abs_path, o->patch_size)) {
        sweep(e->dir);
        *found = 1;
        return TP_EXIT_OK;
    }
    /* one build of this store at a time: a second process waits, then finds it built */
    if (!e->temporary)
        sweep(e->dir);
    e->lock_fd = e->temporary ? -1 : lock_build(out);
    if (e->lock_fd >= 0 && store_matches(out, e->abs_path, o->patch_size)) {
        close(e->lock_fd); /* releases the lock */
        e->lock_fd = -1;
        *found = 1;
    }
    return TP_EXIT_OK;
}

/* The build of e's store into out (sources: one slot, pointed at e's DEM). */
static void entry_build_options(const cache_entry* e, const tp_store_cache_options* o,
                                const char* out, const char** sources, tp_build_options* bo)
{
    tp_build_options_init(bo);
    sources[0] = e->abs_path;
    bo->sources = sources;
    bo->source_count = 1;
    bo->out = out;
    bo->patch_size = o->patch_size;
    bo->fill_max = e->fill_max;
    bo->fill_from = e->from_path[0] ? e->from_path : NULL;
    bo->crs = o->crs;
    bo->z_unit = o->z_unit;
    if (o->resampling == TP_RESAMPLING_CUBIC)
        bo->resampling = TP_RESAMPLING_CUBIC;
}

/* Ends a build of e's store that gave code: the lock released, a temporary folder removed when
 * the build failed. Returns code. */
static int entry_close(cache_entry* e, const char* out, int code, int* temporary_out)
{
    if (e->lock_fd >= 0)
        unlock_build(out, e->lock_fd);
    e->lock_fd = -1;
    if (e->temporary && code != TP_EXIT_OK)
        rmdir(e->dir);
    *temporary_out = e->temporary && code == TP_EXIT_OK;
    return code;
}

int tp_store_cache_get(const char* dem, const tp_store_cache_options* o, char* out, size_t cap,
                       int* temporary_out)
{
    *temporary_out = 0;
    cache_entry e;
    int found;
    int code = entry_open(dem, o, out, cap, &e, &found);
    if (code != TP_EXIT_OK || found)
        return code;
    tp_cli_note("building a store of %s in %s (once; reused next time)", dem, e.dir);
    tp_build_options bo;
    const char* sources[1];
    entry_build_options(&e, o, out, sources, &bo);
    code = tp_store_build(&bo, NULL);
    fflush(stdout);
    return entry_close(&e, out, code, temporary_out);
}

/* ---- a first picture while the store is built (tp_store_cache_begin) ---- */

struct tp_store_cache_job {
    cache_entry e;
    char out[PATH_MAX], preview[PATH_MAX];
    const char* sources[1];
    tp_build_options bo;
    pthread_t thread;
    int started;
    atomic_int done; /* the build has ended; code is its exit code */
    int code;
    int coarsen; /* the preview's */
};

static void* job_run(void* arg)
{
    tp_store_cache_job* j = arg;
    j->code = tp_store_build(&j->bo, NULL);
    atomic_store(&j->done, 1);
    return NULL;
}

/* The preview's name beside the store: NAME-KEY.preview.tpt for NAME-KEY.tpt (sweep() knows it
 * and its temporary files by that name). 0 when it does not fit. */
static int preview_path(const char* out, char* preview, size_t cap)
{
    size_t n = strlen(out);
    return n > 4 && snprintf(preview, cap, "%.*s.preview.tpt", (int)(n - 4), out) < (int)cap;
}

int tp_store_cache_begin(const char* dem, const tp_store_cache_options* o, double preview_samples,
                         char* out, size_t cap, int* temporary_out, char* preview, size_t pcap,
                         tp_store_cache_job** job_out)
{
    *temporary_out = 0;
    *job_out = NULL;
    preview[0] = '\0';
    tp_store_cache_job* j = calloc(1, sizeof *j);
    if (!j) {
        tp_cli_error("out of memory");
        return TP_EXIT_FAILURE;
    }
    int found;
    int code = entry_open(dem, o, j->out, sizeof j->out, &j->e, &found);
    if (code == TP_EXIT_OK && snprintf(out, cap, "%s", j->out) >= (int)cap) {
        tp_cli_error("%s: the cache path is too long", j->e.dir);
        code = entry_close(&j->e, j->out, TP_EXIT_FAILURE, temporary_out);
    }
    if (code != TP_EXIT_OK || found) {
        free(j);
        return code;
    }
    tp_cli_note("building a store of %s in %s (once; reused next time)", dem, j->e.dir);
    entry_build_options(&j->e, o, j->out, j->sources, &j->bo);
    /* the preview: the same build of a coarser grid, quiet; none when the grid is small */
    tp_build_options pb = j->bo;
    tp_build_result pr = {0};
    if (preview_samples > 0 && preview_path(j->out, j->preview, sizeof j->preview)) {
        pb.out = j->preview;
        pb.quiet = 1;
        pb.preview_max_samples = preview_samples;
        code = tp_store_build(&pb, &pr);
        if (code != TP_EXIT_OK && (pr.coarsen <= 1 || tp_interrupted())) {
            /* the sources themselves failed (the message is out), or a signal */
            code = entry_close(&j->e, j->out, code, temporary_out);
            free(j);
            return code;
        }
        if (code != TP_EXIT_OK) /* the preview's own build: the store is built at once */
            pr.coarsen = 1;
    }
    if (pr.coarsen <= 1) { /* a grid small enough to build at once */
        code = tp_store_build(&j->bo, NULL);
        fflush(stdout);
        code = entry_close(&j->e, j->out, code, temporary_out);
        free(j);
        return code;
    }
    tp_cli_note("a first picture from every %d%s post (%dx%d) while the store is built", pr.coarsen,
                pr.coarsen == 2 ? "nd" : "th", pr.width, pr.height);
    /* the preview lives until the job ends: SIGINT or SIGTERM now only ends the view and the
     * build, which remove it (and the lock) on their way out */
    tp_interrupt_hold();
    snprintf(preview, pcap, "%s", j->preview);
    j->coarsen = pr.coarsen;
    *temporary_out = j->e.temporary;
    *job_out = j;
    return TP_EXIT_OK;
}

int tp_store_cache_job_coarsen(const tp_store_cache_job* j)
{
    return j ? j->coarsen : 1;
}

void tp_store_cache_job_start(tp_store_cache_job* j)
{
    if (!j || j->started)
        return;
    j->started = 1;
    if (pthread_create(&j->thread, NULL, job_run, j) != 0) { /* built when finished instead */
        j->started = 0;
        return;
    }
}

int tp_store_cache_job_done(const tp_store_cache_job* j)
{
    return j && atomic_load(&((tp_store_cache_job*)j)->done);
}

int tp_store_cache_job_finish(tp_store_cache_job* j)
{
    if (!j)
        return TP_EXIT_OK;
    if (j->started)
        pthread_join(j->thread, NULL);
    else
        job_run(j);
    fflush(stdout);
    unlink(j->preview);
    int temporary;
    const int code = entry_close(&j->e, j->out, j->code, &temporary);
    free(j);
    tp_interrupt_release();
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
