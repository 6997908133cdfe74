/*
 * vertex_pool.h - where the renderer keeps its items' vertex data on the GPU (Brodersen section
 * 5: fixed-size slots reused least-recently-used). One vertex buffer per level k whose slots
 * hold (2^k+1)^2 vertices, so an item takes the room its level needs, not the finest level's
 * (an item at level 2 of a 65x65 node holds 25 vertices, not 4,225); a map from item key to
 * slot; a free list per level; and, for an item drawn as its own triangle list (an incomplete
 * one, at any level), a region of its level's index buffer, 6 * 4^k indices (a level-k item
 * draws at most 2 * 4^k triangles), that belongs to its slot; 16-bit indices where a slot's
 * vertices can be so numbered (k <= 7: tp_vertex_pool_index_type), 32-bit above. Full buffers
 * grow by a quarter, so a pool holds at most 1.25 times the most a frame drew (past its start):
 * on a software rasteriser, GPU memory is the process's.
 *
 * A slot is named by a handle (>= 0) that stays valid until the next tp_vertex_pool_take: a take
 * may evict any slot not taken in the current frame, or grow a buffer. Every call but the
 * lookups (tp_vertex_pool_slot, tp_vertex_pool_base_vertex, tp_vertex_pool_triangles) needs the
 * GL context the pool was created in to be current; they bind GL_COPY_READ_BUFFER,
 * GL_COPY_WRITE_BUFFER, GL_ARRAY_BUFFER and GL_ELEMENT_ARRAY_BUFFER (the last into the bound
 * vertex array).
 */
#ifndef TP_APP_VERTEX_POOL_H
#define TP_APP_VERTEX_POOL_H

#include "tp_core.h"

#include <stddef.h>
#include <stdint.h>

typedef struct tp_vertex_pool tp_vertex_pool;

/* What a slot holds. */
typedef struct tp_pool_slot {
    /* read-only */
    int64_t key;          /* -1: free */
    int region;           /* its triangle-list region, else -1 */
    uint64_t stamp;       /* last frame it was taken in */
    /* the caller's: what its vertex data was built for (undefined in a fresh slot) */
    int8_t level, nb[4];
    int8_t tin;           /* the TIN rung (tp_render_item.tin), -1: none */
} tp_pool_slot;

/* Pools for levels 0..n of vertices of vertex_bytes each. budget_bytes (0: none) is shared
 * evenly between the n+1 pools: a pool grows (by a quarter) up to its share, then reuses its
 * least-recently-used slots not taken this frame; a frame whose items alone need more grows it
 * past its share (up to max_pool_bytes a pool). Each starts with the slots that fit in
 * initial_bytes (at least 1, at most 4096, and no more than its share holds); regions are made
 * when the first incomplete item of a level needs one (16, then a quarter more each time). Returns NULL with
 * err on failure. */
tp_vertex_pool* tp_vertex_pool_create(int n, size_t vertex_bytes, size_t budget_bytes,
                                      size_t max_pool_bytes, size_t initial_bytes, tp_error* err);
void tp_vertex_pool_destroy(tp_vertex_pool* p); /* accepts NULL */

/* Starts a frame: slots taken from now on are the frame's and are not evicted until the next. */
void tp_vertex_pool_begin_frame(tp_vertex_pool* p);

/* The slot of key at level k (0..n), marked taken this frame: its own, a free one of level k's
 * pool, or that pool's least recently used one not taken this frame; the pool grows when every
 * slot is taken this frame. A key that changed level leaves its old pool's slot. *fresh: the
 * slot's data is not key's (write it). Returns the handle, or -1 when the pool is at
 * max_pool_bytes with every slot taken this frame, or memory ran out. */
int tp_vertex_pool_take(tp_vertex_pool* p, int64_t key, int k, int* fresh);
/* A hint that key will be taken soon: stage 0 brings its map entry towards the cache, stage 1
 * (later, after stage 0) the slot that entry names. Changes nothing; a draw's thousands of
 * takes then wait for memory side by side instead of one after another. */
void tp_vertex_pool_prefetch(const tp_vertex_pool* p, int64_t key, int stage);
tp_pool_slot* tp_vertex_pool_slot(tp_vertex_pool* p, int handle);
int tp_vertex_pool_level(int handle);

/* Writes count (at most the level's (2^k+1)^2) vertices into the slot. */
void tp_vertex_pool_write(tp_vertex_pool* p, int handle, const void* vertices, size_t count);

/* Indices a region of level k holds (a level-k item draws at most 2 * 4^k triangles). */
size_t tp_vertex_pool_region_indices(const tp_vertex_pool* p, int k);
/* Gives the slot a triangle-list region (if it has none) and writes index_count indices (at
 * most tp_vertex_pool_region_indices, uint32, relative to the slot's first vertex; stored as
 * tp_vertex_pool_index_type says) into it.
 * Returns 0 if no region could be made (the slot then has none). */
int tp_vertex_pool_write_triangles(tp_vertex_pool* p, int handle, const uint32_t* indices,
                                   size_t index_count);
/* Gives the slot's region back (nothing if it has none). */
void tp_vertex_pool_drop_triangles(tp_vertex_pool* p, int handle);

/* For drawing: the vertex buffer of level k's pool; the base vertex of a slot (its first
 * vertex in that buffer); the index buffer of level k's regions (0 while there is none); the
 * slot's region as a byte offset into it and an index count (returns 0 without a region). */
unsigned int tp_vertex_pool_vertex_buffer(const tp_vertex_pool* p, int k);
int32_t tp_vertex_pool_base_vertex(const tp_vertex_pool* p, int handle);
unsigned int tp_vertex_pool_index_buffer(const tp_vertex_pool* p, int k);
/* The type of the indices in level k's regions: GL_UNSIGNED_SHORT where a slot holds at most
 * 65536 vertices (k <= 7), else GL_UNSIGNED_INT. */
unsigned int tp_vertex_pool_index_type(const tp_vertex_pool* p, int k);
size_t tp_vertex_pool_triangles(const tp_vertex_pool* p, int handle, size_t* offset_bytes);

/* Bytes of the GPU buffers it holds (vertex pools and regions). */
size_t tp_vertex_pool_gpu_bytes(const tp_vertex_pool* p);
/* Of those, the bytes of the triangle-list regions' index buffers. */
size_t tp_vertex_pool_index_bytes(const tp_vertex_pool* p);

#endif
