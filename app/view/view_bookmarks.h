/*
 * view_bookmarks.h - the viewer's bookmarks (bookmarks.h keeps the file): `--bookmark NAME` and
 * `--save-bookmark NAME` on the command line, Ctrl+1..9 (save the view as "view N"), 1..9 (back to
 * "view N") and Tab / Shift+Tab (every bookmark of the file in turn) in the window.
 */
#ifndef TP_APP_VIEW_BOOKMARKS_H
#define TP_APP_VIEW_BOOKMARKS_H

#include "view.h"

/* The bookmarks file of this view: --bookmarks FILE, else the default one of the DEM
 * (tp_bookmarks_default_path). 0 after a message when there is none. */
int tp_view_bookmarks_path(const view_options* o, char* out, size_t cap);

/* Checks, before anything is drawn, that the bookmarks file of this view can be read when it is
 * asked for: missing is fine (no bookmarks yet), but not a FIFO or a device (tp_bookmarks_check).
 * 0 after one line on stderr naming it. */
int tp_view_bookmarks_check(const view_options* o);

/* The camera of bookmark name (viewport and field of view from o). 0 after a one-line message
 * on stderr: an unknown name lists the known ones, a bad file names its line. */
int tp_view_bookmark_camera(const tp_view_scene* v, const view_options* o, const char* name,
                            tp_camera* cam);

/* Saves cam as bookmark name (replacing one of that name). Returns 1 with what happened, one
 * line, in line (cap bytes: "bookmark 'NAME' saved in PATH"); 0 with the reason in err. */
int tp_view_bookmark_save(const tp_view_scene* v, const view_options* o, const tp_camera* cam,
                          const char* name, char* line, size_t cap, tp_error* err);

/* Moves cam to bookmark name (window keys 1..9: "view N"); *index becomes its place in the file.
 * Returns 1 with a line in line (cap bytes); 0 (cam unchanged) with the reason in err when there
 * is none of that name or it cannot be shown. */
int tp_view_bookmark_recall(const tp_view_scene* v, const view_options* o, tp_camera* cam,
                            const char* name, int* index, char* line, size_t cap, tp_error* err);

/* Moves cam to the bookmark `step` places after *index in file order (wrapping; *index -1: none
 * yet) and updates *index. Returns 1 with a line in line (cap bytes); 0 with the reason in err
 * when nothing changed. */
int tp_view_bookmark_cycle(const tp_view_scene* v, const view_options* o, tp_camera* cam,
                           int* index, int step, char* line, size_t cap, tp_error* err);

#endif
