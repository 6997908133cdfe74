/* tin_int.h - the error-bounded TIN's private functions (tin.c), for its tiled build
 * (tin_tiles.c). */
#ifndef TP_CORE_TIN_INT_H
#define TP_CORE_TIN_INT_H

#include "internal.h"
#include "tp_tin.h"

/* ---- error-bounded TIN (tin.c) ---- */

/* Marks TIN_FORCE (1) in cls (width * height, zeroed by the caller) at every corner of a valid
 * cell that touches an invalid one (TP_TIN_CUT_VOIDS); returns whether it marked any. */
int tp__tin_void_classes(const float* h, int w, int hg, uint8_t* cls);

/* The bound errors are compared with, as floats (each error rounded up to a float): the largest
 * float not above e, so that "err <= bound" means err <= e. An error of exactly e is allowed
 * (common on integer heights at e = 1: a margin below e cost 15% more triangles on Mt Hood);
 * another double formula may measure it 1e-12 m above e. */
float tp__tin_bound(double e);

/* tp_tin_build after its checks, on a grid of at least 2x2 with a valid sample: cls (NULL or
 * one byte per sample: 0 free, 1 forced, 2 skipped) says which samples are inserted first and
 * which are never measured; cut drops the triangles over invalid cells. */
tp_status tp__tin_build(const float* heights, int width, int height, double max_error_m,
                        const uint8_t* cls, int cut, tp_tin** out, tp_error* err);

#endif
