/* view_bookmarks.c - the viewer's bookmarks (see view_bookmarks.h). */
#include "view_bookmarks.h"

#include "bookmarks.h"
#include "camera_pose.h"
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int tp_view_bookmarks_path(const view_options* o, char* out, size_t cap)
{
    if (o->bookmarks_path) {
        snprintf(out, cap, "%s", o->bookmarks_path);
        return 1;
    }
    return tp_bookmarks_default_path(o->path, out, cap);
}

int tp_view_bookmarks_check(const view_options* o)
{
    char path[4096];
    tp_error err = {{0}};
    if (!tp_view_bookmarks_path(o, path, sizeof path))
        return 1; /* no file at all: said when one is asked for */
    if (tp_bookmarks_check(path, &err))
        return 1;
    tp_cli_error("bookmarks: %s", err.message);
    return 0;
}

static int load(const view_options* o, char* path, size_t path_cap, tp_bookmarks* b, tp_error* err)
{
    if (!tp_view_bookmarks_path(o, path, path_cap)) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "bookmarks: no file (set $XDG_CONFIG_HOME or $HOME, or --bookmarks FILE)");
        return 0;
    }
    return tp_bookmarks_load(path, b, err);
}

static int to_camera(const tp_view_scene* v, const view_options* o, const tp_bookmark* bm,
                     int w, int h, tp_camera* cam)
{
    if (bm->geo && !tp_georef_has_geo(v->georef)) {
        tp_cli_error("bookmark '%s' is --camera-geo, but %s has no geographic "
                     "position",
                     bm->name, v->path);
        return 0;
    }
    return tp_camera_from_option_georef(v->georef, bm->geo, bm->v, o->vs.fov_deg, w, h, cam,
                                        "view");
}

int tp_view_bookmark_camera(const tp_view_scene* v, const view_options* o, const char* name,
                            tp_camera* cam)
{
    char path[4096];
    tp_error err = {{0}};
    tp_bookmarks b;
    if (!load(o, path, sizeof path, &b, &err)) {
        tp_cli_error("--bookmark: %s", err.message);
        return 0;
    }
    const tp_bookmark* bm = tp_bookmarks_find(&b, name);
    int ok = 0;
    if (!bm) {
        char names[2048];
        tp_bookmarks_names(&b, names, sizeof names);
        tp_cli_error("--bookmark: no bookmark '%s' in %s (known: %s)", name, path, names);
    } else {
        ok = to_camera(v, o, bm, o->vs.w, o->vs.h, cam);
    }
    tp_bookmarks_free(&b);
    return ok;
}

int tp_view_bookmark_save(const tp_view_scene* v, const view_options* o, const tp_camera* cam,
                          const char* name, char* line, size_t cap, tp_error* err)
{
    char path[4096], text[512];
    tp_bookmarks b;
    if (!load(o, path, sizeof path, &b, err))
        return 0;
    /* the camera as C prints it; the --camera-geo form when the DEM has one */
    tp_camera_text_georef(v->georef, cam, text, sizeof text);
    const char* geo = strstr(text, "--camera-geo ");
    char entry[700];
    snprintf(entry, sizeof entry, "%s %s", name, geo ? geo : text);
    if (!geo) { /* "--camera E,N,H,YAW,PITCH" alone */
        char* extra = strstr(entry + strlen(name) + 2, " --");
        if (extra)
            *extra = '\0';
    }
    tp_bookmark bm;
    tp_error why = {{0}};
    int ok = tp_bookmark_parse_line(entry, &bm, &why) == 1 && tp_bookmarks_set(&b, &bm, &why);
    if (!ok)
        tp_error_set(err, TP_ERR_INVALID_ARG, "bookmark '%s' not saved: %s", name, why.message);
    else if ((ok = tp_bookmarks_save(path, &b, err)))
        snprintf(line, cap, "bookmark '%s' saved in %s", name, path);
    tp_bookmarks_free(&b);
    return ok;
}

int tp_view_bookmark_cycle(const tp_view_scene* v, const view_options* o, tp_camera* cam,
                           int* index, int step, char* line, size_t cap, tp_error* err)
{
    char path[4096];
    tp_bookmarks b;
    if (!load(o, path, sizeof path, &b, err))
        return 0;
    if (b.count == 0) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "bookmarks: none in %s (Ctrl+1..9 saves the view)",
                     path);
        return 0;
    }
    int n = (int)b.count, i = *index < 0 ? (step > 0 ? 0 : n - 1) : ((*index + step) % n + n) % n;
    tp_camera c;
    int ok = to_camera(v, o, &b.items[i], cam->viewport_w_px, cam->viewport_h_px, &c);
    if (ok) {
        *cam = c;
        *index = i;
        snprintf(line, cap, "bookmark %d of %d: '%s'", i + 1, n, b.items[i].name);
    } else {
        tp_error_set(err, TP_ERR_INVALID_ARG, "bookmark '%s' cannot be shown (see the terminal)",
                     b.items[i].name);
    }
    tp_bookmarks_free(&b);
    return ok;
}

int tp_view_bookmark_recall(const tp_view_scene* v, const view_options* o, tp_camera* cam,
                            const char* name, int* index, char* line, size_t cap, tp_error* err)
{
    char path[4096];
    tp_bookmarks b;
    if (!load(o, path, sizeof path, &b, err))
        return 0;
    const tp_bookmark* bm = tp_bookmarks_find(&b, name);
    int ok = 0;
    if (!bm) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "no bookmark '%s' in %s (Ctrl+%s saves it)", name,
                     path, name + strlen(name) - 1);
    } else if (!to_camera(v, o, bm, cam->viewport_w_px, cam->viewport_h_px, cam)) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "bookmark '%s' cannot be shown (see the terminal)",
                     name);
    } else {
        *index = (int)(bm - b.items);
        snprintf(line, cap, "bookmark '%s'", name);
        ok = 1;
    }
    tp_bookmarks_free(&b);
    return ok;
}
