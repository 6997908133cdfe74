/*
 * test_writes.c - outputs written whole or not at all (io/src/atomic_write.cpp), end to end:
 * `terrapatch view` and `export` run as children on a "full disk" (RLIMIT_FSIZE with SIGXFSZ
 * ignored, so write() fails with EFBIG, as on ENOSPC, without root), with symlinks planted at
 * the temporary names older versions used, and killed with SIGTERM/SIGINT while they write
 * (inotify says when the temporary file or folder appears). Each time: the exit status, an
 * older output byte for byte as it was, and no temporary file left in the folder. `los` with
 * several outputs on a full disk replaces none of them; `contours` and `los` sent a signal just
 * after their last rename end as having written (exit 0).
 */
#define _GNU_SOURCE
#include "tp_io.h"
#include "tp_test.h"
#include "tp_test_child.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define TP_TMP_PREFIX "tp_writes_"
#include "tp_test_tmp.h"


typedef struct child_opts {
    rlim_t fsize_limit;    /* bytes; 0: none */
    const char* plant_dir; /* plant symlinks at the old predictable temporary names here */
    const char* err_path;  /* the child's stderr */
} child_opts;

static const char* terrapatch(void)
{
    const char* exe = getenv("TP_TERRAPATCH");
    if (!exe || access(exe, X_OK) != 0)
        SKIP("TP_TERRAPATCH not set: the terrapatch binary is not built");
    return exe;
}

static void data_path(char* buf, size_t cap, const char* file)
{
    if (!tp_test_data_path(buf, cap, "TP_SHARED_DATA_DIR", file))
        SKIP("data file %s not found (set TP_SHARED_DATA_DIR)", buf);
}

/* Symlinks to dir/victim at the names terrapatch <= ff441b2 wrote its temporaries to: the
 * image writer's PATH.tmp<pid>.png and the text outputs' PATH.tmp<pid>. Runs in the child. */
static void plant(const char* dir)
{
    const char* names[] = {"shot.png.tmp%ld.png", "stats.json.tmp%ld"};
    char victim[600], link[700];
    snprintf(victim, sizeof victim, "%s/victim", dir);
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char n[100];
        snprintf(n, sizeof n, names[i], (long)getpid());
        snprintf(link, sizeof link, "%s/%s", dir, n);
        if (symlink(victim, link) != 0)
            _exit(99);
    }
}

/* Starts `terrapatch args...` (NULL-terminated) with SIGINT/SIGTERM at their defaults. */
static pid_t start(const char* const* args, const child_opts* o)
{
    const char* exe = terrapatch();
    const char* argv[64];
    int n = 0;
    argv[n++] = exe;
    for (int i = 0; args[i] && n < 62; i++)
        argv[n++] = args[i];
    argv[n] = NULL;
    /* Mesa's unloaded driver looks leaky to LeakSanitizer (as in test_view.c) */
    static char asan[512];
    char** envp = tp_test_child_environment(asan, sizeof asan);
    fflush(NULL);
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) {
        int null = open("/dev/null", O_RDWR);
        int err = open(o->err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (null < 0 || err < 0)
            _exit(98);
        dup2(null, 0);
        dup2(null, 1);
        dup2(err, 2);
        signal(SIGINT, SIG_DFL);
        signal(SIGTERM, SIG_DFL);
        if (o->fsize_limit) {
            struct rlimit rl = {o->fsize_limit, o->fsize_limit};
            signal(SIGXFSZ, SIG_IGN); /* write() then fails with EFBIG: a full disk */
            if (setrlimit(RLIMIT_FSIZE, &rl) != 0)
                _exit(97);
        }
        if (o->plant_dir)
            plant(o->plant_dir); /* getpid() is the pid terrapatch will have */
        execve(exe, (char* const*)argv, envp);
        _exit(96);
    }
    return pid;
}

/* The exit status; 128 + the signal for a child a signal killed (as a shell says). */
static int finish(pid_t pid)
{
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            FAIL("waitpid: %s", strerror(errno));
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

static int run(const char* const* args, const child_opts* o, char* err, size_t err_cap)
{
    int rc = finish(start(args, o));
    FILE* f = fopen(o->err_path, "r");
    size_t got = f ? fread(err, 1, err_cap - 1, f) : 0;
    err[got] = '\0';
    if (f)
        fclose(f);
    return rc;
}

/* The names in dir, sorted, each followed by one space ("" for an empty folder). */
static void entries(const char* dir, char* out, size_t cap)
{
    char names[64][256];
    int n = 0;
    DIR* d = opendir(dir);
    ASSERT_TRUE(d != NULL);
    struct dirent* e;
    while ((e = readdir(d)) != NULL && n < 64)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            snprintf(names[n++], sizeof names[0], "%s", e->d_name);
    closedir(d);
    for (int i = 1; i < n; i++) /* insertion sort: a handful of names */
        for (int j = i; j > 0 && strcmp(names[j - 1], names[j]) > 0; j--) {
            char t[256];
            memcpy(t, names[j], sizeof t);
            memcpy(names[j], names[j - 1], sizeof t);
            memcpy(names[j - 1], t, sizeof t);
        }
    out[0] = '\0';
    for (int i = 0; i < n; i++) {
        strncat(out, names[i], cap - strlen(out) - 2);
        strcat(out, " ");
    }
}

static void put_file(const char* path, const void* data, size_t size)
{
    FILE* f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    ASSERT_EQ_INT((int)size, (int)fwrite(data, 1, size, f));
    ASSERT_EQ_INT(0, fclose(f));
}

/* The whole file (malloc'd), or NULL if it cannot be read. */
static char* get_file(const char* path, size_t* size)
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char* buf = malloc(n > 0 ? (size_t)n : 1);
    *size = buf ? fread(buf, 1, (size_t)n, f) : 0;
    fclose(f);
    return buf;
}

/* Asserts path holds exactly the bytes old (old_size). */
static void expect_same(const char* path, const char* old, size_t old_size)
{
    size_t size = 0;
    char* now = get_file(path, &size);
    ASSERT_TRUE(now != NULL);
    EXPECT_EQ_INT((int)old_size, (int)size);
    EXPECT_TRUE(size == old_size && memcmp(now, old, size) == 0);
    free(now);
}

/* ---------------------------------------------------------------------------------------------
 * A full disk
 */
TEST(screenshot_on_full_disk_keeps_the_old_png)
{
    char dem[1024], shot[600], errf[600], err[4096], list[2048];
    data_path(dem, sizeof dem, "craterlake-elev-16bit-30m.tif");
    const char* dir = make_tmp_dir();
    snprintf(shot, sizeof shot, "%s/shot.png", dir);
    snprintf(errf, sizeof errf, "%s.err", dir);
    child_opts o = {.err_path = errf};
    const char* good[] = {"view", "--headless", "--no-hud", "--size", "320x200",
                          "--screenshot", shot, dem, NULL};
    ASSERT_EQ_INT(0, run(good, &o, err, sizeof err));
    size_t old_size = 0;
    char* old = get_file(shot, &old_size);
    ASSERT_TRUE(old != NULL && old_size > 20000); /* about 39 KB */
    /* a different image, on a disk that takes 16 KiB more */
    o.fsize_limit = 16384;
    const char* full[] = {"view", "--headless", "--no-hud", "--wireframe", "--size", "320x200",
                          "--screenshot", shot, dem, NULL};
    EXPECT_EQ_INT(1, run(full, &o, err, sizeof err));
    EXPECT_CONTAINS(err, "shot.png: cannot write: File too large");
    expect_same(shot, old, old_size);
    entries(dir, list, sizeof list);
    EXPECT_EQ_STR("shot.png ", list);
    free(old);
    remove(errf);
}

TEST(stats_json_on_full_disk_keeps_the_old_file)
{
    char dem[1024], stats[600], errf[600], err[4096], list[2048];
    data_path(dem, sizeof dem, "craterlake-elev-16bit-30m.tif");
    const char* dir = make_tmp_dir();
    snprintf(stats, sizeof stats, "%s/stats.json", dir);
    snprintf(errf, sizeof errf, "%s.err", dir);
    const char old[] = "{\"old\": true}\n";
    put_file(stats, old, sizeof old - 1);
    /* the JSON is about 500 bytes; the limit applies to the child's stderr file too */
    child_opts o = {.err_path = errf, .fsize_limit = 400};
    const char* args[] = {"view", "--headless", "--no-hud", "--size", "64x48",
                          "--stats-json", stats, dem, NULL};
    EXPECT_EQ_INT(1, run(args, &o, err, sizeof err));
    EXPECT_CONTAINS(err, "stats.json: cannot write: File too large");
    expect_same(stats, old, sizeof old - 1);
    entries(dir, list, sizeof list);
    EXPECT_EQ_STR("stats.json ", list);
    remove(errf);
}

TEST(export_on_full_disk_keeps_the_old_mesh)
{
    char dem[1024], out[600], errf[600], err[4096], list[2048];
    data_path(dem, sizeof dem, "craterlake-elev-16bit-30m.tif");
    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/mesh.vtk", dir);
    snprintf(errf, sizeof errf, "%s.err", dir);
    const char old[] = "# vtk DataFile Version 4.2\nold\n";
    put_file(out, old, sizeof old - 1);
    child_opts o = {.err_path = errf, .fsize_limit = 1 << 20}; /* the mesh is about 10 MB */
    const char* args[] = {"export", "--full", dem, "-o", out, NULL};
    EXPECT_EQ_INT(1, run(args, &o, err, sizeof err));
    EXPECT_CONTAINS(err, "mesh.vtk: cannot write: File too large");
    expect_same(out, old, sizeof old - 1);
    entries(dir, list, sizeof list);
    EXPECT_EQ_STR("mesh.vtk ", list);
    remove(errf);
}

/* ---------------------------------------------------------------------------------------------
 * Outputs checked before the work
 */
TEST(stats_json_to_a_missing_folder_writes_no_screenshot)
{
    char dem[1024], shot[600], stats[600], errf[600], err[4096], list[2048];
    data_path(dem, sizeof dem, "craterlake-elev-16bit-30m.tif");
    const char* dir = make_tmp_dir();
    snprintf(shot, sizeof shot, "%s/shot.png", dir);
    snprintf(stats, sizeof stats, "%s/no-such-folder/stats.json", dir);
    snprintf(errf, sizeof errf, "%s.err", dir);
    child_opts o = {.err_path = errf};
    const char* args[] = {"view", "--headless", "--no-hud", "--size", "64x48", "--screenshot",
                          shot, "--stats-json", stats, dem, NULL};
    EXPECT_EQ_INT(1, run(args, &o, err, sizeof err));
    EXPECT_CONTAINS(err, "no-such-folder/stats.json: cannot write");
    entries(dir, list, sizeof list);
    EXPECT_EQ_STR("", list); /* no shot.png */
    remove(errf);
}

TEST(export_to_a_missing_folder_fails_before_reading_the_dem)
{
    char out[600], errf[600], err[4096];
    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/no-such-folder/mesh.vtp", dir);
    snprintf(errf, sizeof errf, "%s.err", dir);
    child_opts o = {.err_path = errf};
    /* the DEM does not exist either: the output is what is reported */
    const char* args[] = {"export", "/nonexistent-dir/dem.tif", "-o", out, NULL};
    EXPECT_EQ_INT(1, run(args, &o, err, sizeof err));
    EXPECT_CONTAINS(err, "no-such-folder/mesh.vtp: cannot write");
    remove(errf);
}

/* ---------------------------------------------------------------------------------------------
 * Symlinks at predictable names
 */
TEST(symlinks_at_old_temporary_names_are_not_followed)
{
    char dem[1024], shot[600], stats[600], victim[600], errf[600], err[4096];
    data_path(dem, sizeof dem, "craterlake-elev-16bit-30m.tif");
    const char* dir = make_tmp_dir();
    snprintf(shot, sizeof shot, "%s/shot.png", dir);
    snprintf(stats, sizeof stats, "%s/stats.json", dir);
    snprintf(victim, sizeof victim, "%s/victim", dir);
    snprintf(errf, sizeof errf, "%s.err", dir);
    const char secret[] = "someone else's file\n";
    put_file(victim, secret, sizeof secret - 1);
    child_opts o = {.err_path = errf, .plant_dir = dir};
    const char* args[] = {"view", "--headless", "--no-hud", "--size", "64x48", "--screenshot",
                          shot, "--stats-json", stats, dem, NULL};
    EXPECT_EQ_INT(0, run(args, &o, err, sizeof err));
    expect_same(victim, secret, sizeof secret - 1);
    /* the outputs are files of their own, not links to the victim */
    struct stat st;
    ASSERT_EQ_INT(0, lstat(shot, &st));
    EXPECT_TRUE(S_ISREG(st.st_mode));
    ASSERT_EQ_INT(0, lstat(stats, &st));
    EXPECT_TRUE(S_ISREG(st.st_mode));
    int w = 0, h = 0;
    uint8_t* px = NULL;
    tp_error e;
    EXPECT_OK(tp_image_read_rgba(shot, &w, &h, &px, &e));
    EXPECT_EQ_INT(64, w);
    free(px);
    remove(errf);
}

/* ---------------------------------------------------------------------------------------------
 * Signals while writing
 */

/* Waits (up to 60 s) for an event of mask in the folder watched by fd on a name holding part
 * (exactly part when exact; a folder if want_dir); then returns 1. 0 if the child exited first
 * or time ran out. */
static int wait_for_name(int fd, uint32_t mask, const char* part, int exact, int want_dir,
                         pid_t child)
{
    char buf[4096] __attribute__((aligned(__alignof__(struct inotify_event))));
    for (int waited_ms = 0; waited_ms < 60000; waited_ms += 20) {
        struct pollfd p = {.fd = fd, .events = POLLIN};
        int r = poll(&p, 1, 20);
        if (r > 0) {
            ssize_t n = read(fd, buf, sizeof buf);
            for (char* q = buf; n > 0 && q < buf + n;) {
                struct inotify_event* ev = (struct inotify_event*)q;
                if ((ev->mask & mask) && ev->len &&
                    (exact ? !strcmp(ev->name, part) : strstr(ev->name, part) != NULL) &&
                    (!want_dir || (ev->mask & IN_ISDIR)))
                    return 1;
                q += sizeof *ev + ev->len;
            }
        }
        siginfo_t info = {0};
        if (waitid(P_PID, (id_t)child, &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid)
            return 0; /* exited (still to be reaped by finish) */
    }
    return 0;
}

/* Until a name holding ".tmp" is created (a folder if want_dir). */
static int wait_for_temp(int fd, int want_dir, pid_t child)
{
    return wait_for_name(fd, IN_CREATE, ".tmp", 0, want_dir, child);
}

/* Exports dem (craterlake, full resolution) to dir/name over an older file (and, for a .vtm, an
 * older folder of pieces), sends sig once the temporary file (or folder) appears, plus
 * delay_ms, and checks what is left. Returns 0 when the signal came too late to test anything:
 * the write had already finished (the .vtk lives for some 20-40 ms; a loaded machine may wake
 * us after that), so the child died of the signal's default action with the new file complete,
 * no "interrupted" line and nothing temporary left (all checked); the caller tries again. */
static int export_killed_once(const char* name, const char* extra, int sig, int delay_ms)
{
    char dem[1024], out[600], errf[600], err[4096], list[2048], pieces[600], piece[700];
    data_path(dem, sizeof dem, "craterlake-elev-16bit-30m.tif");
    (void)terrapatch();
    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/%s", dir, name);
    snprintf(errf, sizeof errf, "%s.err", dir);
    const char old[] = "old mesh\n";
    put_file(out, old, sizeof old - 1);
    int vtm = strstr(name, ".vtm") != NULL;
    if (vtm) { /* an older folder of pieces, as a .vtm export leaves it */
        snprintf(pieces, sizeof pieces, "%s/mesh", dir);
        snprintf(piece, sizeof piece, "%s/mesh_0.vtp", pieces);
        ASSERT_EQ_INT(0, mkdir(pieces, 0777));
        put_file(piece, old, sizeof old - 1);
    }
    int fd = inotify_init1(IN_CLOEXEC);
    ASSERT_TRUE(fd >= 0);
    ASSERT_TRUE(inotify_add_watch(fd, dir, IN_CREATE) >= 0);
    child_opts o = {.err_path = errf};
    const char* args[] = {"export", "--full", dem, "-o", out, extra, NULL};
    pid_t pid = start(args, &o);
    int seen = wait_for_temp(fd, vtm, pid);
    if (seen && delay_ms) {
        struct timespec ts = {0, delay_ms * 1000000L};
        nanosleep(&ts, NULL);
    }
    if (seen)
        kill(pid, sig);
    close(fd);
    int rc = finish(pid);
    ASSERT_TRUE(seen); /* else the export never wrote a temporary file */
    FILE* f = fopen(errf, "r");
    size_t got = f ? fread(err, 1, sizeof err - 1, f) : 0;
    err[got] = '\0';
    if (f)
        fclose(f);
    entries(dir, list, sizeof list);
    size_t now_size = 0;
    char* now = get_file(out, &now_size);
    const int replaced = now && !(now_size == sizeof old - 1 && !memcmp(now, old, now_size));
    free(now);
    if (!strstr(err, "interrupted") && replaced) { /* too late: the write was complete */
        EXPECT_TRUE(rc == 0 || rc == 128 + sig);                   /* done, or killed after */
        EXPECT_EQ_STR(vtm ? "mesh mesh.vtm " : "mesh.vtk ", list); /* nothing temporary */
        remove(errf);
        return 0;
    }
    EXPECT_EQ_INT(128 + sig, rc);
    EXPECT_CONTAINS(err, "terrapatch export: interrupted\n");
    expect_same(out, old, sizeof old - 1);
    EXPECT_EQ_STR(vtm ? "mesh mesh.vtm " : "mesh.vtk ", list);
    if (vtm) {
        expect_same(piece, old, sizeof old - 1);
        entries(pieces, list, sizeof list);
        EXPECT_EQ_STR("mesh_0.vtp ", list);
    }
    remove(errf);
    return 1;
}

/* Up to 5 tries: each must leave things right; at least one must land during the write. */
static void export_killed(const char* name, const char* extra, int sig, int delay_ms)
{
    for (int attempt = 0; attempt < 5; attempt++)
        if (export_killed_once(name, extra, sig, delay_ms))
            return;
    FAIL("the signal came after the write every time (5 tries): nothing was interrupted");
}

TEST(sigterm_during_vtk_export_leaves_no_temporary_file)
{
    export_killed("mesh.vtk", NULL, SIGTERM, 0);
}

TEST(sigint_during_vtk_export_leaves_no_temporary_file)
{
    export_killed("mesh.vtk", NULL, SIGINT, 0);
}

TEST(sigterm_during_vtm_export_leaves_no_temporary_folder)
{
    export_killed("mesh.vtm", "--per-patch", SIGTERM, 300);
}

/* ---------------------------------------------------------------------------------------------
 * Several outputs: all or none, and done once renamed
 */
/* los --json --csv on a disk with room for the JSON but not the CSV: neither is replaced (all
 * or none), nothing temporary is left, and the message says so. */
TEST(los_outputs_on_full_disk_keep_every_old_file)
{
    char dem[1024], json[600], csv[600], errf[600], err[4096], list[2048];
    data_path(dem, sizeof dem, "N42E001.hgt");
    const char* dir = make_tmp_dir();
    snprintf(json, sizeof json, "%s/a.json", dir);
    snprintf(csv, sizeof csv, "%s/a.csv", dir);
    snprintf(errf, sizeof errf, "%s.err", dir);
    const char* args[] = {"los",    dem,  "--from", "42.5,1.5", "--to", "42.52,1.53",
                          "--json", json, "--csv",  csv,        NULL};
    /* once with room (the store cache built, the sizes known: the JSON about 1 KB, the CSV
     * about 14 KB) */
    child_opts o = {.err_path = errf};
    ASSERT_EQ_INT(0, run(args, &o, err, sizeof err));
    size_t json_size = 0, csv_size = 0;
    free(get_file(json, &json_size));
    free(get_file(csv, &csv_size));
    ASSERT_TRUE(json_size < 4096 && csv_size > 8192);
    const char old_json[] = "{\"old\": true}\n", old_csv[] = "old,csv\n";
    put_file(json, old_json, sizeof old_json - 1);
    put_file(csv, old_csv, sizeof old_csv - 1);
    o.fsize_limit = 8192;
    EXPECT_EQ_INT(1, run(args, &o, err, sizeof err));
    EXPECT_CONTAINS(err, "a.csv: cannot write: File too large");
    EXPECT_CONTAINS(err, "a.json, ");
    EXPECT_CONTAINS(err, "written (all or none");
    expect_same(json, old_json, sizeof old_json - 1);
    expect_same(csv, old_csv, sizeof old_csv - 1);
    entries(dir, list, sizeof list);
    EXPECT_EQ_STR("a.csv a.json ", list);
    remove(errf);
}

/* args (a command writing dir/name, NULL-terminated) run over a cached store and sent sig the
 * moment name is renamed into place (inotify): the output is complete, so the command ends as
 * having written it (exit 0, its "wrote" line), not 128 + sig with the new file in place. */
static void killed_after_rename(const char* const* args, const char* dir, const char* name, int sig)
{
    char errf[600], err[4096], path[700], wrote[800];
    snprintf(errf, sizeof errf, "%s.err", dir);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    child_opts o = {.err_path = errf};
    ASSERT_EQ_INT(0, run(args, &o, err, sizeof err)); /* the store cache built */
    remove(path);
    int fd = inotify_init1(IN_CLOEXEC);
    ASSERT_TRUE(fd >= 0);
    ASSERT_TRUE(inotify_add_watch(fd, dir, IN_MOVED_TO) >= 0);
    pid_t pid = start(args, &o);
    const int seen = wait_for_name(fd, IN_MOVED_TO, name, 1, 0, pid);
    if (seen)
        kill(pid, sig);
    close(fd);
    const int rc = finish(pid);
    ASSERT_TRUE(seen);
    FILE* f = fopen(errf, "r");
    size_t got = f ? fread(err, 1, sizeof err - 1, f) : 0;
    err[got] = '\0';
    if (f)
        fclose(f);
    EXPECT_EQ_INT(0, rc);
    snprintf(wrote, sizeof wrote, "terrapatch %s: wrote %s\n", args[0], path);
    EXPECT_CONTAINS(err, wrote);
    EXPECT_TRUE(strstr(err, "interrupted") == NULL);
    EXPECT_EQ_INT(0, access(path, F_OK));
    remove(errf);
}

TEST(sigterm_after_the_contours_rename_exits_0)
{
    char dem[1024], out[600];
    data_path(dem, sizeof dem, "N42E001.hgt");
    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/c.gpkg", dir);
    const char* args[] = {"contours", dem, "--interval", "100", "-o", out, NULL};
    killed_after_rename(args, dir, "c.gpkg", SIGTERM);
}

TEST(sigint_after_the_los_renames_exits_0)
{
    char dem[1024], json[600], csv[600];
    data_path(dem, sizeof dem, "N42E001.hgt");
    const char* dir = make_tmp_dir();
    snprintf(json, sizeof json, "%s/l.json", dir);
    snprintf(csv, sizeof csv, "%s/l.csv", dir);
    const char* args[] = {"los",    dem,  "--from", "42.5,1.5", "--to", "42.52,1.53",
                          "--json", json, "--csv",  csv,        NULL};
    killed_after_rename(args, dir, "l.csv", SIGINT); /* the CSV: the last renamed */
}

/* ---------------------------------------------------------------------------------------------
 * The writer itself (tp_file_*)
 */
TEST(file_writer_abort_and_failures_leave_the_old_file)
{
    char path[600], list[2048];
    const char* dir = make_tmp_dir();
    snprintf(path, sizeof path, "%s/out.txt", dir);
    put_file(path, "old\n", 4);
    tp_file_writer* w = NULL;
    tp_error e;
    ASSERT_OK(tp_file_begin(path, &w, &e));
    ASSERT_OK(tp_file_append(w, "new", 3, &e));
    entries(dir, list, sizeof list);
    EXPECT_TRUE(strncmp(list, "out.txt out.txt.tmp", 19) == 0); /* the temporary, beside */
    EXPECT_EQ_INT(19 + 8 + 1, (int)strlen(list));                /* 8 random characters */
    tp_file_abort(w);
    expect_same(path, "old\n", 4);
    entries(dir, list, sizeof list);
    EXPECT_EQ_STR("out.txt ", list);
    /* a folder that does not exist, a folder as the name */
    char bad[700];
    snprintf(bad, sizeof bad, "%s/none/out.txt", dir);
    EXPECT_STATUS(TP_ERR_IO, tp_file_write(bad, "x", 1, &e));
    EXPECT_CONTAINS(e.message, "none/out.txt: cannot write: No such file or directory");
    EXPECT_STATUS(TP_ERR_IO, tp_output_check(bad, &e));
    EXPECT_STATUS(TP_ERR_IO, tp_output_check(dir, &e));
    EXPECT_CONTAINS(e.message, "it is a folder");
    EXPECT_OK(tp_output_check(path, &e));
    /* and a write that succeeds replaces it */
    ASSERT_OK(tp_file_write(path, "new\n", 4, &e));
    expect_same(path, "new\n", 4);
    entries(dir, list, sizeof list);
    EXPECT_EQ_STR("out.txt ", list);
}

#define TESTS(X)                                                                                   \
    X(screenshot_on_full_disk_keeps_the_old_png)                                                   \
    X(stats_json_on_full_disk_keeps_the_old_file)                                                  \
    X(export_on_full_disk_keeps_the_old_mesh)                                                      \
    X(stats_json_to_a_missing_folder_writes_no_screenshot)                                         \
    X(export_to_a_missing_folder_fails_before_reading_the_dem)                                     \
    X(symlinks_at_old_temporary_names_are_not_followed)                                            \
    X(sigterm_during_vtk_export_leaves_no_temporary_file)                                          \
    X(sigint_during_vtk_export_leaves_no_temporary_file)                                           \
    X(sigterm_during_vtm_export_leaves_no_temporary_folder)                                        \
    X(file_writer_abort_and_failures_leave_the_old_file)                                           \
    X(los_outputs_on_full_disk_keep_every_old_file)                                                \
    X(sigterm_after_the_contours_rename_exits_0)                                                   \
    X(sigint_after_the_los_renames_exits_0)
TP_TEST_MAIN(TESTS)
