/* bookmarks.c - named camera views in a text file (see bookmarks.h). */
#define _POSIX_C_SOURCE 200809L
#include "bookmarks.h"

#include "atomic_file.h"

#include "tp_io.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char* skip_space(const char* s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    return s;
}

/* "a,b,c,d,e" and nothing but spaces after it. */
static int five_numbers(const char* s, double v[5])
{
    for (int i = 0; i < 5; i++) {
        char* end;
        s = skip_space(s);
        errno = 0;
        v[i] = strtod(s, &end);
        if (end == s || !isfinite(v[i]))
            return 0;
        s = skip_space(end);
        if (i < 4 && *s++ != ',')
            return 0;
    }
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
        s++;
    return *s == '\0';
}

int tp_bookmark_parse_line(const char* line, tp_bookmark* out, tp_error* err)
{
    const char* s = skip_space(line);
    if (*s == '\0' || *s == '\n' || *s == '\r' || *s == '#')
        return 0;
    const char* opt = strstr(s, "--camera");
    while (opt && opt > s && opt[-1] != ' ' && opt[-1] != '\t')
        opt = strstr(opt + 1, "--camera");
    if (!opt) {
        tp_error_set(err, TP_ERR_BAD_DATA,
                     "expected NAME --camera-geo LAT,LON,H,YAW,PITCH, got '%.60s'", s);
        return -1;
    }
    size_t name_len = (size_t)(opt - s);
    while (name_len > 0 && (s[name_len - 1] == ' ' || s[name_len - 1] == '\t'))
        name_len--;
    if (name_len == 0) {
        tp_error_set(err, TP_ERR_BAD_DATA, "no name before %.12s", opt);
        return -1;
    }
    if (name_len >= TP_BOOKMARK_NAME_SIZE) {
        tp_error_set(err, TP_ERR_BAD_DATA, "name longer than %d characters",
                     TP_BOOKMARK_NAME_SIZE - 1);
        return -1;
    }
    for (size_t i = 0; i < name_len; i++) { /* what tp_bookmarks_set refuses, refused here */
        if (i + 8 <= name_len && !strncmp(s + i, "--camera", 8)) {
            tp_error_set(err, TP_ERR_BAD_DATA, "a name may not hold '--camera': '%.*s'",
                         (int)name_len, s);
            return -1;
        }
        if ((unsigned char)s[i] < 0x20 && s[i] != '\t') {
            tp_error_set(err, TP_ERR_BAD_DATA, "a control character (0x%02x) in the name",
                         (unsigned char)s[i]);
            return -1;
        }
    }
    int geo = strncmp(opt, "--camera-geo", 12) == 0;
    const char* nums = opt + (geo ? 12 : 8);
    if (*nums != ' ' && *nums != '\t') {
        tp_error_set(err, TP_ERR_BAD_DATA, "expected --camera-geo or --camera, got '%.20s'", opt);
        return -1;
    }
    double v[5];
    if (!five_numbers(nums, v)) {
        tp_error_set(err, TP_ERR_BAD_DATA, "%s: expected five numbers %s, got '%.60s'",
                     geo ? "--camera-geo" : "--camera",
                     geo ? "LAT,LON,H,YAW,PITCH" : "E,N,H,YAW,PITCH", skip_space(nums));
        return -1;
    }
    if (geo && (v[0] < -90 || v[0] > 90)) {
        tp_error_set(err, TP_ERR_BAD_DATA, "--camera-geo: latitude %g is outside [-90, 90]", v[0]);
        return -1;
    }
    memcpy(out->name, s, name_len);
    out->name[name_len] = '\0';
    out->geo = geo;
    memcpy(out->v, v, sizeof v);
    return 1;
}

void tp_bookmark_format(const tp_bookmark* b, char* out, size_t cap)
{
    if (b->geo)
        snprintf(out, cap, "%s --camera-geo %.9f,%.9f,%.2f,%.2f,%.2f", b->name, b->v[0], b->v[1],
                 b->v[2], b->v[3], b->v[4]);
    else
        snprintf(out, cap, "%s --camera %.3f,%.3f,%.2f,%.2f,%.2f", b->name, b->v[0], b->v[1],
                 b->v[2], b->v[3], b->v[4]);
}

void tp_bookmarks_free(tp_bookmarks* b)
{
    free(b->items);
    b->items = NULL;
    b->count = 0;
}

static int append(tp_bookmarks* b, const tp_bookmark* bm)
{
    tp_bookmark* items = realloc(b->items, (b->count + 1) * sizeof *items);
    if (!items)
        return 0;
    b->items = items;
    b->items[b->count++] = *bm;
    return 1;
}

int tp_bookmarks_check(const char* path, tp_error* err)
{
    struct stat st;
    if (stat(path, &st) != 0 && errno == ENOENT)
        return 1;
    return tp_input_check(path, "a bookmarks (text)", 0, err) == TP_OK;
}

int tp_bookmarks_load(const char* path, tp_bookmarks* out, tp_error* err)
{
    memset(out, 0, sizeof *out);
    struct stat st;
    if (stat(path, &st) != 0 && errno == ENOENT)
        return 1; /* no file yet: no bookmarks */
    if (!tp_bookmarks_check(path, err))
        return 0;
    FILE* f = fopen(path, "r");
    if (!f) {
        tp_error_set(err, TP_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
        return 0;
    }
    char line[1024];
    int line_no = 0, ok = 1;
    while (ok && fgets(line, sizeof line, f)) {
        line_no++;
        size_t len = strlen(line);
        if (len == sizeof line - 1 && line[len - 1] != '\n' && !feof(f)) {
            tp_error_set(err, TP_ERR_BAD_DATA, "%s:%d: line longer than %zu characters", path,
                         line_no, sizeof line - 2);
            ok = 0;
            break;
        }
        tp_bookmark bm;
        tp_error why = {{0}};
        int r = tp_bookmark_parse_line(line, &bm, &why);
        if (r < 0) {
            tp_error_set(err, TP_ERR_BAD_DATA, "%s:%d: %s", path, line_no, why.message);
            ok = 0;
        } else if (r > 0 && !append(out, &bm)) {
            tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
            ok = 0;
        }
    }
    if (ok && ferror(f)) {
        tp_error_set(err, TP_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
        ok = 0;
    }
    fclose(f);
    if (!ok)
        tp_bookmarks_free(out);
    return ok;
}

/* mkdir -p of path's folder. */
static int make_parent(const char* path, tp_error* err)
{
    char dir[4096];
    if (strlen(path) >= sizeof dir)
        return 1; /* the writer says what is wrong */
    strcpy(dir, path);
    char* slash = strrchr(dir, '/');
    if (!slash || slash == dir)
        return 1;
    *slash = '\0';
    for (char* p = dir + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
            tp_error_set(err, TP_ERR_IO, "%s: cannot create the folder %s: %s", path, dir,
                         strerror(errno));
            return 0;
        }
        *p = '/';
    }
    if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
        tp_error_set(err, TP_ERR_IO, "%s: cannot create the folder %s: %s", path, dir,
                     strerror(errno));
        return 0;
    }
    return 1;
}

int tp_bookmarks_save(const char* path, const tp_bookmarks* b, tp_error* err)
{
    if (!make_parent(path, err))
        return 0;
    tp_atomic_file a;
    if (!tp_atomic_open(&a, path)) {
        tp_error_set(err, TP_ERR_IO, "%s: cannot write (see above)", path);
        return 0;
    }
    fprintf(a.f, "# terrapatch bookmarks: NAME --camera-geo LAT,LON,H,YAW,PITCH (H as drawn)\n");
    for (size_t i = 0; i < b->count; i++) {
        char line[512];
        tp_bookmark_format(&b->items[i], line, sizeof line);
        fprintf(a.f, "%s\n", line);
    }
    if (!tp_atomic_commit(&a)) {
        tp_error_set(err, TP_ERR_IO, "%s: not written (see above)", path);
        return 0;
    }
    return 1;
}

const tp_bookmark* tp_bookmarks_find(const tp_bookmarks* b, const char* name)
{
    for (size_t i = 0; i < b->count; i++)
        if (strcmp(b->items[i].name, name) == 0)
            return &b->items[i];
    return NULL;
}

int tp_bookmarks_set(tp_bookmarks* b, const tp_bookmark* bm, tp_error* err)
{
    /* the name must read back as itself */
    char line[512];
    tp_bookmark back;
    tp_bookmark_format(bm, line, sizeof line);
    if (strchr(bm->name, '\n') || strchr(bm->name, '\r') || strstr(bm->name, "--camera") ||
        tp_bookmark_parse_line(line, &back, NULL) != 1 || strcmp(back.name, bm->name)) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "bookmark name '%.60s' cannot be kept: it must not be empty, start or end "
                     "with a space or '#', nor hold a line break or '--camera'",
                     bm->name);
        return 0;
    }
    for (size_t i = 0; i < b->count; i++)
        if (strcmp(b->items[i].name, bm->name) == 0) {
            b->items[i] = *bm;
            return 1;
        }
    if (!append(b, bm)) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return 0;
    }
    return 1;
}

void tp_bookmarks_names(const tp_bookmarks* b, char* out, size_t cap)
{
    if (cap == 0)
        return;
    out[0] = '\0';
    if (b->count == 0) {
        snprintf(out, cap, "none");
        return;
    }
    size_t at = 0;
    for (size_t i = 0; i < b->count && at < cap; i++) {
        int n = snprintf(out + at, cap - at, "%s'%s'", i ? ", " : "", b->items[i].name);
        if (n < 0)
            break;
        at += (size_t)n;
    }
}

int tp_bookmarks_default_path(const char* dem_path, char* out, size_t cap)
{
    const char* base = strrchr(dem_path, '/');
    base = base ? base + 1 : dem_path;
    const char* xdg = getenv("XDG_CONFIG_HOME");
    const char* home = getenv("HOME");
    int n;
    if (xdg && xdg[0] == '/')
        n = snprintf(out, cap, "%s/terrapatch/bookmarks/%s.bookmarks", xdg, base);
    else if (home && home[0])
        n = snprintf(out, cap, "%s/.config/terrapatch/bookmarks/%s.bookmarks", home, base);
    else
        return 0;
    return n > 0 && (size_t)n < cap;
}
