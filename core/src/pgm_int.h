/* pgm_int.h - Persistent Grid Mapping's vertex mapping (pgm.c), for its error (pgm_error.c). */
#ifndef TP_CORE_PGM_INT_H
#define TP_CORE_PGM_INT_H

#include "internal.h"
#include "tp_pgm.h"

/* Persistent Grid Mapping (pgm.c): where grid vertex (i, j) of frame f meets the base plane,
 * ground[0..1] (E, N) and ground[2..3] (level-0 grid x, y), the level l and parent weight W_p
 * tp_pgm_map_vertex reads its height with (the height itself is left to the caller). */
void tp__pgm_map_ground(const tp_pgm_frame* f, const tp_pgm_pyramid* p, int i, int j,
                        double ground[4], int* level, double* wp);

#endif
