/*
 * planner_cli.h - the prologue and outputs every planner command shares (`point`, `los`,
 * `viewshed`, `contours`, `profile`): the pieces their option parsers are made of, a position
 * read from the command line and placed on the ground (with the messages), the ground opened,
 * the posts of a window read, and the outputs written (the text or JSON on stdout, JSON and CSV
 * files atomically, a gnuplot PNG). Each command keeps its own options, computation and report
 * in its cmd_*.c. app/commands/planner_cli.c.
 *
 * Messages are those of cli.h: "terrapatch CMD: ..." on stderr, cmd naming the command ("los").
 */
#ifndef TP_APP_PLANNER_CLI_H
#define TP_APP_PLANNER_CLI_H

#include "gnuplot.h"
#include "ground.h"
#include "options.h"
#include "position.h"
#include "scene.h"

#include "tp_core.h"

#include <stddef.h>
#include <stdio.h>

/* ---- the command line ---- */

/* Where a planner command reads the ground: the DEM or store, and how to open it. */
typedef struct tp_planner_source {
    const char* path;      /* the DEM (any raster GDAL reads) or store (.tpt) */
    const char* cache_dir; /* --cache-dir: the store cache for a DEM; NULL for the default */
    tp_scene_options dem;  /* the DEM options (scene.h) */
} tp_planner_source;

/* No path, the default cache and the DEM options' defaults. */
void tp_planner_source_init(tp_planner_source* s);

/* Adds --cache-dir and the DEM options (tp_scene_options_add) to a parse, read into s. */
void tp_planner_source_add(tp_options* p, tp_planner_source* s);

/* Parses a planner command's arguments (options.h): its own options (own: a table, with its
 * handler for CODE options, or NULL), the source's options (tp_planner_source_add) and one
 * operand, the DEM or store, into src->path: none is "missing DEM", a second one "more than
 * one DEM given" followed by hint (e.g. " (quote a position with spaces: --observer
 * \"45.37 -121.69\")", or ""). Returns -1 when every argument was read, else the exit code
 * that ends the command: 0 after the help (help), 2 after a usage error. */
int tp_planner_parse(const char* cmd, int argc, char** argv, void (*help)(void),
                     tp_option_table own, tp_planner_source* src, const char* hint);

/* Prints a planner command's help: text (usage, what it does, its own options), the source's
 * options (--cache-dir and the DEM options), a blank line, then after (examples, exit
 * status). */
void tp_planner_help(const char* text, const char* after);

/* ---- positions and the ground ---- */

/* Reads text (NUL-terminated) as one position, without a height: both readings of an ambiguous
 * band letter S (position.h) are kept for tp_planner_choose to take the one on the DEM. 1 with
 * *pos; else 0 after "terrapatch CMD: WHAT 'TEXT': why" (what names it: "--from", "position"),
 * with "; a position is LAT LON, latitude first: 'B A'?" when the two numbers swapped would
 * read; the caller exits with TP_EXIT_USAGE. */
int tp_planner_position(const char* cmd, const char* what, const char* text,
                        tp_position_readings* pos);

/* The reading of pos to put on g: the only one; of two, the one on the DEM, after "terrapatch
 * CMD: note: read 'INPUT' as band S (...); the other reading, zone Z south (...), is off PATH"
 * on stderr. 1 with *out; 0 after "terrapatch CMD: PATH: 'INPUT' is ambiguous ..." when both
 * readings or neither are on the DEM (the caller exits with TP_EXIT_FAILURE). */
int tp_planner_choose(const char* cmd, const char* path, tp_ground* g,
                      const tp_position_readings* pos, const char* input, tp_position* out);

/* What a message about pos off the DEM ends with: "; with latitude and longitude swapped (LON
 * LAT) it is on the DEM: a position is LAT LON, latitude first" when that is so (pos typed as
 * latitude/longitude), else "". */
void tp_planner_swap_hint(tp_ground* g, const tp_position* pos, char* out, size_t cap);

/* ---- a list of positions (profile's --through) ---- */

/* Positions read in order from a command line, each with its readings (tp_planner_position). */
typedef struct tp_planner_positions {
    char** text;                    /* each as typed (malloc'd), blanks around it trimmed */
    tp_position_readings* readings; /* count of them */
    size_t count;
} tp_planner_positions;

/* Reads values[0 .. count-1], each the value of one option what ("--through"): one position, or
 * several separated by ';' ("45.3,-121.7; 45.4,-121.6"), into out, in order. 1; else 0 after
 * "terrapatch CMD: WHAT 'TEXT': why" (tp_planner_position; an empty piece: "the position is
 * empty"), out empty; the caller exits with TP_EXIT_USAGE. */
int tp_planner_positions_read(const char* cmd, const char* what, const char* const* values,
                              size_t count, tp_planner_positions* out);

/* Places each position of p on g as tp_planner_locate does (the reading on the DEM of an
 * ambiguous one; on the DEM and not in a void) and writes its render-CRS easting and northing
 * into en (2 * p->count doubles). 1; else 0 after "terrapatch CMD: PATH: WHAT: why" (why as
 * tp_ground_locate's, with tp_planner_swap_hint), the caller exits with TP_EXIT_FAILURE. */
int tp_planner_positions_place(const char* cmd, const char* path, tp_ground* g, const char* what,
                               const tp_planner_positions* p, double* en);

void tp_planner_positions_free(tp_planner_positions* p); /* accepts an empty one */

/* Checks that each of the count paths can be written (tp_atomic_check_dir), NULL and "-"
 * (stdout) passed over; 0 after the first one's message. */
int tp_planner_check_outputs(const char* const* paths, int count);

/* tp_ground_open of src with its options: the exit code, *g on TP_EXIT_OK. */
int tp_planner_ground_open(const char* cmd, const tp_planner_source* src, tp_ground** g);

/* tp_planner_choose, then tp_ground_locate: 1 with grid (x, y) and the ground's height; else
 * 0 after "terrapatch CMD: PATH: why" (input is the position as typed; off the DEM with
 * tp_planner_swap_hint, in a void with tp_ground_void_hint). */
int tp_planner_locate(const char* cmd, const char* path, tp_ground* g,
                      const tp_position_readings* pos, const char* input, double* x, double* y,
                      double* height_m);

/* ---- a window of posts ---- */

/* A window of the ground's posts, read whole. */
typedef struct tp_planner_window {
    int x0, y0, w, h; /* posts (x0, y0) .. (x0 + w - 1, y0 + h - 1) of the render grid */
    size_t n;         /* w * h */
    double gt[6];     /* the window's geotransform (the grid's, moved to post (x0, y0)) */
    float* z;         /* after tp_planner_window_read: the heights, row by row, NaN in a void */
    double read_s;    /* the seconds the reading took */
} tp_planner_window;

/* The window of the posts within radius_m of grid post (cx, cy) along each axis (a square;
 * radius_m 0: the whole grid), clipped to the grid. Nothing is read yet. */
void tp_planner_window_around(tp_ground* g, int cx, int cy, double radius_m,
                              tp_planner_window* win);

/* The window x0..x1, y0..y1 (posts, inclusive, on the grid). */
void tp_planner_window_set(tp_ground* g, int x0, int y0, int x1, int y1, tp_planner_window* win);

/* Reads the window's heights (tp_ground_read_posts, with progress naming progress_cmd when not
 * NULL) into a new win->z: TP_OK, or out of memory and tp_ground_read_posts's errors. */
tp_status tp_planner_window_read(tp_ground* g, tp_planner_window* win, const char* progress_cmd,
                                 tp_error* err);

void tp_planner_window_free(tp_planner_window* win);

/* The window of posts a command reads (contours, terrain): the whole grid; with
 * area (E0, N0, E1, N1 in the render CRS, E0 < E1 and N0 < N1; NULL for none) the posts inside
 * it; with around (NULL for none; around_text as typed) the posts within radius_m along each
 * axis (a square) of the position, which may be in a void. 1 with *win set
 * (tp_planner_window_set: nothing read yet); 0 after one line naming path (the position off
 * the DEM or ambiguous, the area outside the DEM). */
int tp_planner_window_choose(const char* cmd, const char* path, tp_ground* g, const double* area,
                             const tp_position_readings* around, const char* around_text,
                             double radius_m, tp_planner_window* win);

/* Writes values (win->n bytes) as a one-band Byte raster on the window's georeference
 * (tp_byte_raster_write, band description), with SIGINT/SIGTERM only recorded during the write
 * and, once it is written, the command's end with its output (tp_interrupt_finished). */
tp_status tp_planner_raster_write(tp_ground* g, const char* out, const uint8_t* values,
                                  const tp_planner_window* win, const char* description,
                                  tp_error* err);

/* The same for win->n floats (NaN: nodata) as a Float32 raster (tp_float_raster_write). */
tp_status tp_planner_float_raster_write(tp_ground* g, const char* out, const float* values,
                                        const tp_planner_window* win, const char* description,
                                        tp_error* err);

/* The window's posts fit one run (max_posts) and the memory left at bytes_per_post a post;
 * else 0 after one line naming path and what to do (--area or --around). */
int tp_planner_window_fits(const char* path, const tp_planner_window* pw, size_t max_posts,
                           size_t bytes_per_post);

/* The summary's "window" line (part: a part of the grid_w x grid_h grid, else the whole DEM)
 * and "ground" line (the heights read; step_m > 0: the store's step). */
void tp_planner_print_ground(const tp_planner_window* pw, int grid_w, int grid_h, int part,
                             double step_m);

/* ---- the outputs ---- */

/* Writes one output of report to f. */
typedef void (*tp_planner_write_fn)(FILE* f, void* report);

typedef struct tp_planner_outputs {
    const char* json; /* a JSON file; "-": the JSON on stdout instead of the text; NULL: none */
    const char* csv;  /* a CSV file, or NULL */
    const char* png;  /* a gnuplot PNG, or NULL */
    tp_planner_write_fn write_text, write_json, write_csv;
    tp_gnuplot_script_fn write_plot; /* with png: png_width_px x png_height_px */
    int png_width_px, png_height_px;
} tp_planner_outputs;

/* Prints the text (the JSON for json "-") on stdout, then writes the JSON file, the CSV file
 * (each printed through atomic_file.h) and the PNG (tp_gnuplot_draw) that o names, all or
 * none (tp_file_set_* in tp_io.h): 1 when all were written, after "terrapatch CMD: wrote PATH" on
 * stderr for each, with SIGINT/SIGTERM ignored from then on (tp_interrupt_finished: the command
 * ends with its outputs written); 0 after a line saying what failed and that nothing was
 * written (every older file as it was). */
int tp_planner_write_outputs(const char* cmd, const tp_planner_outputs* o, void* report);

/* The exit after the work: after SIGINT/SIGTERM tp_cli_interrupted(); else code, stdout
 * flushed (tp_cli_finish) when it is TP_EXIT_OK. */
int tp_planner_finish(int code);

#endif /* TP_APP_PLANNER_CLI_H */
