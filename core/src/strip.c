/* strip.c - one triangle strip with degenerate triangles per level.
 *
 * Based on: Vanek & Jezek, "Real-Time Terrain Visualization on PC" (WSCG 2004), section 2:
 * rows alternate direction and each row ends with its last vertex repeated twice, so that the
 * next row starts at an even position of the strip and keeps the winding (the paper's
 * "one index appended in order to maintain a correct vertex orientation").
 */
#include "internal.h"
#include "tp_terrain.h"

#include <assert.h>

size_t tp_strip_index_count(int k)
{
    assert(k >= 0 && k <= TP_MAX_N);
    size_t v = ((size_t)1 << k) + 1;
    return (2 * v + 2) * (v - 1);
}

/* The paper's loop with m = n = v; emit() is called once per index. */
#define TP__STRIP_LOOP(v, emit)                                                                \
    for (size_t i = 0; i + 1 < (v); i++) {                                                     \
        if (i % 2) {                                                                           \
            for (size_t j = (v); j-- > 0;) {                                                   \
                emit((i + 1) * (v) + j);                                                       \
                emit(i * (v) + j);                                                             \
            }                                                                                  \
            emit((i + 1) * (v));                                                               \
            emit((i + 1) * (v));                                                               \
        } else {                                                                               \
            for (size_t j = 0; j < (v); j++) {                                                 \
                emit(i * (v) + j);                                                             \
                emit((i + 1) * (v) + j);                                                       \
            }                                                                                  \
            emit((i + 2) * (v) - 1);                                                           \
            emit((i + 2) * (v) - 1);                                                           \
        }                                                                                      \
    }

void tp_strip_build_u32(int k, uint32_t* indices, size_t index_capacity)
{
    assert(indices && index_capacity >= tp_strip_index_count(k));
    (void)index_capacity; /* only asserted */
    size_t v = ((size_t)1 << k) + 1, at = 0;
#define TP__EMIT32(x) (indices[at++] = (uint32_t)(x))
    TP__STRIP_LOOP(v, TP__EMIT32)
#undef TP__EMIT32
}

void tp_strip_build_u16(int k, uint16_t* indices, size_t index_capacity)
{
    assert(k <= 7 && indices && index_capacity >= tp_strip_index_count(k));
    (void)index_capacity; /* only asserted */
    size_t v = ((size_t)1 << k) + 1, at = 0;
#define TP__EMIT16(x) (indices[at++] = (uint16_t)(x))
    TP__STRIP_LOOP(v, TP__EMIT16)
#undef TP__EMIT16
}
