/*
 * bookmarks.h - named camera views kept in a small text file (the viewer's Ctrl+1..9, 1..9,
 * Tab and `view --bookmark NAME`). No GL: the file and its lines only.
 *
 * The file: one bookmark a line, "NAME --camera-geo LAT,LON,H,YAW,PITCH" (as the viewer's C key
 * and tp_camera_text_georef write a camera; H in the drawn space, as --camera-geo takes it), or
 * "NAME --camera E,N,H,YAW,PITCH" for a DEM without geographic position (a local CRS). NAME is
 * everything before " --camera" with the spaces around it trimmed: it may hold spaces ("view 3",
 * "OP north ridge"), not a line break, not "--camera". Blank lines and lines starting with '#'
 * are skipped (and not kept when the file is written again). Written atomically
 * (atomic_file.h): a failed save leaves the older file as it was.
 *
 * Where: $XDG_CONFIG_HOME/terrapatch/bookmarks/FILE.bookmarks (else ~/.config/...), FILE being
 * the DEM's (or store's) file name without its folder: the DEM's own folder is often read-only
 * (shared data) and a copy of the DEM elsewhere keeps its views. `view --bookmarks FILE` names
 * another file.
 */
#ifndef TP_APP_BOOKMARKS_H
#define TP_APP_BOOKMARKS_H

#include "tp_core.h"

#include <stddef.h>

#define TP_BOOKMARK_NAME_SIZE 128

typedef struct tp_bookmark {
    char name[TP_BOOKMARK_NAME_SIZE];
    int geo;     /* 1: v is LAT,LON,H,YAW,PITCH (--camera-geo); 0: E,N,H,YAW,PITCH (--camera) */
    double v[5];
} tp_bookmark;

typedef struct tp_bookmarks {
    tp_bookmark* items; /* malloc'd; file order */
    size_t count;
} tp_bookmarks;

/* Reads one line (no '\n' needed) into *out. Returns 1, 0 for a blank or '#' line (nothing
 * written), -1 with the reason in err for a malformed line: no " --camera" part, an empty name,
 * not five finite numbers, a latitude outside [-90, 90]. */
int tp_bookmark_parse_line(const char* line, tp_bookmark* out, tp_error* err);

/* Writes b as its line (no '\n'), e.g. "view 3 --camera-geo 45.373,-121.695,3200.00,20.00,-30.00". */
void tp_bookmark_format(const tp_bookmark* b, char* out, size_t cap);

/* Reads the file at path into *out (zeroed first). A missing file is no bookmarks (returns 1,
 * count 0). Returns 0 with err "PATH:LINE: why" for a malformed line, "PATH: ..." when it cannot
 * be read; *out then holds nothing to free. */
int tp_bookmarks_load(const char* path, tp_bookmarks* out, tp_error* err);

/* 1 when path can be loaded: missing (no bookmarks yet) or a regular file; else 0 with the
 * reason in err ("PATH: cannot open: it is a FIFO ..."): a FIFO would block, /dev/zero never
 * end. */
int tp_bookmarks_check(const char* path, tp_error* err);

/* Writes every bookmark to path, atomically, creating path's folder (one level: the default
 * location's "bookmarks" folder, and its parents) when missing. Returns 0 with err. */
int tp_bookmarks_save(const char* path, const tp_bookmarks* b, tp_error* err);

/* The bookmark named name (exact match), or NULL. */
const tp_bookmark* tp_bookmarks_find(const tp_bookmarks* b, const char* name);

/* Replaces the bookmark of that name, or appends it. Returns 0 with err for a name that cannot
 * be kept (empty after trimming, a line break, "--camera", too long) or out of memory. */
int tp_bookmarks_set(tp_bookmarks* b, const tp_bookmark* bm, tp_error* err);

/* The names, quoted and comma-separated ("'view 1', 'ridge'"), or "none". */
void tp_bookmarks_names(const tp_bookmarks* b, char* out, size_t cap);

void tp_bookmarks_free(tp_bookmarks* b);

/* The default file of a DEM or store path (see above). Returns 0 when no home folder is known
 * (neither $XDG_CONFIG_HOME nor $HOME) or cap is too small. */
int tp_bookmarks_default_path(const char* dem_path, char* out, size_t cap);

#endif
