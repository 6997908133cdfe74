/*
 * tp_io/store.h - terrain stores (.tpt): a built tp_tree on disk, written and read.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_STORE_H
#define TP_IO_STORE_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Terrain stores (.tpt): a built tp_tree on disk (io/src/store_*.cpp; format in docs/store.md)
 *
 * A versioned little-endian file: a header (geometry, georeference, quantisation, CRS, the
 * sources it was built from), the node table (every node's tp_node_meta, laid out as in memory so
 * that it is mapped, not decoded), the location table (the offset, size, CRC32 and codec of every
 * node's data) and each node's samples, compressed (and, from format 3, the cell mask of the
 * nodes above the leaves that are drawn in part; from format 4, the filled bits of the nodes
 * holding filled void samples). Written atomically through tp_file_* (an
 * interrupted or failed write leaves no file); read with one open file shared by threads
 * (pread), each node checked against its CRC32 when read. Formats 2 and 3 are written and read
 * on little-endian hosts only (TP_ERR_BACKEND elsewhere).
 */
#define TP_STORE_VERSION 4 /* 4: filled bits of the nodes holding filled void samples */

typedef struct tp_store_header {
    tp_tree_geometry geometry;
    double geotransform[6];    /* of the fitted grid, render CRS */
    double height_step_m;
    double quant_max_error_m;
    double err_unit_steps;
    size_t valid_samples, nodata_samples; /* of the source grid (padding not counted) */
    const char* crs_wkt;       /* render CRS as WKT; "" for none */
    const char* notes;         /* free text: sources, mosaic and warp decisions ('\n'-separated) */
} tp_store_header;

typedef struct tp_store_writer tp_store_writer;
/* Starts writing path (tp_file_begin) and writes the header. TP_ERR_INVALID_ARG for a geometry
 * that is not the one of (n, src_width, src_height) (the message names the field), a CRS or notes
 * over 16 MiB; TP_ERR_IO; each with a message naming path. *out written only on success. The
 * writer writes each node's table entries into place as the node is added and keeps one bit per
 * node in memory, never the tables or the data. */
tp_status tp_store_writer_begin(const char* path, const tp_store_header* header,
                                tp_store_writer** out, tp_error* err);
/* Adds one node (any order; each node exactly once): its meta, its (2^n+1)^2 global
 * quantised heights (INT32_MIN = not drawn), which the writer stores relative to meta->qmin,
 * compressed, and its cell mask (tp_node_mask_words(n) words, as the tree builder emits it;
 * stored only for a node of scale >= 1 drawn in part, may be NULL for others), appended to the
 * file at once. TP_ERR_INVALID_ARG (nothing written, w still usable) for a node that does not
 * exist or was added already, unknown flags, a missing mask, a drawn height outside meta's
 * qmin..qmax or a range wider than 65534 steps; TP_ERR_IO when the write fails
 * (then every later call and the commit fail the same way: abort w). */
tp_status tp_store_writer_add_node(tp_store_writer* w, int64_t node, const tp_node_meta* meta,
                                   const int32_t* q, const uint16_t* mask, tp_error* err);
/* tp_store_writer_add_node with the node's filled bits (tp_node_filled_words(n) words, as the
 * tree builder's emit_filled gives them): required when meta has TP_NODE_HAS_FILLED, NULL
 * otherwise; stored compressed after the node's samples and mask (docs/store.md, format 4).
 * TP_ERR_INVALID_ARG also for bits missing or given against the flag, a bit on a sample not
 * drawn or past the samples, or the flag with no bit set. */
tp_status tp_store_writer_add_node_filled(tp_store_writer* w, int64_t node,
                                          const tp_node_meta* meta, const int32_t* q,
                                          const uint16_t* mask, const uint16_t* filled,
                                          tp_error* err);
/* A node's stored bytes as a store holds them (tp_store_read_stored): copied from one store to
 * another without decoding (`terrapatch merge` joins the parts of a build so). */
typedef struct tp_store_stored {
    const uint8_t* bytes; /* the node's data: samples, cell mask, filled bits, as encoded */
    size_t size;
    uint32_t crc;         /* CRC32 of bytes */
    int codec;            /* as the location table names it */
} tp_store_stored;
/* Adds one node from its stored bytes (read from another store of the same n by
 * tp_store_read_stored, with the same meta): appended as they are. The checks of
 * tp_store_writer_add_node on the node and its meta, and the CRC32 of the bytes against
 * stored->crc (TP_ERR_BAD_DATA when it differs); TP_ERR_IO as there. */
tp_status tp_store_writer_add_stored(tp_store_writer* w, int64_t node, const tp_node_meta* meta,
                                     const tp_store_stored* stored, tp_error* err);
/* The header's values known only once the whole grid has been read (a build that reads its
 * sources once): they replace the header's quant_max_error_m, valid_samples and nodata_samples
 * given to tp_store_writer_begin; commit writes the header again with them (tp_file_rewrite of
 * the same bytes with those three fields and its CRC32 changed; the format is unchanged). Any
 * time before commit; the last call wins. */
void tp_store_writer_set_totals(tp_store_writer* w, double quant_max_error_m,
                                size_t valid_samples, size_t nodata_samples);
/* Replaces the header's notes by notes of the same length in bytes (for counts known only at
 * the end: the begin's notes reserve room, e.g. with trailing spaces); commit writes them.
 * TP_ERR_INVALID_ARG when the length differs (w is unchanged). */
tp_status tp_store_writer_set_notes(tp_store_writer* w, const char* notes, tp_error* err);
/* Checksums the tables (read back), writes the footer and makes the file (tp_file_commit). Frees w, whatever
 * happens. TP_ERR_INVALID_ARG when a node is missing (the message says how many and the first),
 * TP_ERR_IO; on failure no file is left and an older path is as it was. */
tp_status tp_store_writer_commit(tp_store_writer* w, tp_error* err);
void tp_store_writer_abort(tp_store_writer* w); /* accepts NULL; leaves no file */

typedef struct tp_store tp_store;
typedef struct tp_store_info {
    tp_store_header header;    /* strings owned by the store */
    uint32_t version;
    int remote;                /* 1: read over HTTP (tp_store_open was given an http(s) URL) */
    uint64_t file_bytes, data_bytes, table_bytes;
    double bytes_per_sample;   /* file_bytes / (src_width * src_height) */
} tp_store_info;

/* Opens a store, path a local file or an http:// or https:// URL (read with range requests
 * through GDAL's /vsicurl/: io/src/range_file.hpp; its tables are then read in one request and
 * kept in memory, not mapped; a file replaced on the server since open fails every later read
 * with "URL: ...: the file changed on the server since it was opened (...): open it again",
 * TP_ERR_IO, and is never mixed with the one opened). Checks magic ("not a terrapatch store"), the header's checksum, the version (a
 * newer one: "written by a newer terrapatch (format N; this one reads up to M)"; an older one:
 * "written by an older terrapatch (format N; ...): rebuild it with terrapatch build"), the
 * geometry against the one n and the source size define, the footer's and both tables'
 * checksums, every meta's flags and range, and that every node's data lies inside the file (one
 * pass of pread over the tables, 128 bytes per node). Then maps the tables read-only: the store
 * takes a few KB of the process's own memory whatever its node count (the mapped pages are the
 * file's, shared with the page cache). Do not truncate an open store (a mapping past the end of
 * its file is SIGBUS) nor rewrite it in place (the metas would change under the tree; node reads
 * check their location's bounds again); terrapatch itself always writes a new file and renames
 * it. TP_ERR_BAD_DATA (damaged, truncated, an older or newer format, not a store) / TP_ERR_IO
 * (cannot read or map; a FIFO, device or folder; an HTTP failure) / TP_ERR_BACKEND (a big-endian host) with a
 * message naming path; *out written only on success. */
tp_status tp_store_open(const char* path, tp_store** out, tp_error* err);
void tp_store_close(tp_store* s); /* accepts NULL */
/* 1 once a read of a store over HTTP found its file replaced on the server (every later read
 * fails); 0 otherwise and always for a local file. Thread-safe. */
int tp_store_changed(const tp_store* s);
void tp_store_get_info(const tp_store* s, tp_store_info* out);
/* Every node's meta (node_count of them, in id order; delta[k > n], eps[][kn >= n] and pad_
 * are 0), owned by s and valid while s is open: a read-only mapping of the file's node table. */
const tp_node_meta* tp_store_metas(const tp_store* s, size_t* count);
/* Reads, checks (CRC32) and decodes node's samples into samples ((2^n+1)^2 uint16 relative to
 * its qmin, TP_TREE_NO_HEIGHT where not drawn; sample_capacity at least that; node in
 * 0..node_count-1). With sample_capacity >= tp_tree_block_words(n), the node's cell mask
 * follows the samples (stored, or made from its samples or flags): a block for tp_tree_attach. Thread-safe: any number of threads may read one open store at once (pread;
 * each thread keeps its own zstd context and buffers for its lifetime). About 15 us for a
 * 65x65 node (docs/store.md). TP_ERR_BAD_DATA for a checksum or decoding failure, a sample
 * outside the node's range or a cell mask that marks a cell with an undrawn corner whole, TP_ERR_IO for a read failure, each with a message naming the file,
 * the node ("node 38 (scale 0, column 3, row 4)") and its byte offset; samples are written
 * only on success. */
tp_status tp_store_read_node(const tp_store* s, int64_t node, uint16_t* samples,
                             size_t sample_capacity, tp_error* err);
/* A store over HTTP: reads the stored bytes of nodes[0..count) ahead, concurrently (up to 16
 * range requests in flight, the ranges of nodes closer than 16 KB in the file merged into one
 * request of at most 512 KB) and keeps them in memory (at most 64 MB, the oldest dropped
 * first), so that a later tp_store_read_node or tp_store_read_stored of any of them makes no
 * request (its bytes still checked against the node's CRC32; read with the same precondition
 * as every read, so a file replaced on the server is never mixed in). For the reader that knows
 * which nodes it will ask for one at a time (the roots, a measure's leaves, a normal-map
 * block's nodes): one round trip or a few instead of one a node. A range that cannot be read is
 * not reported here: the node's own read asks again and reports it. Returns the number of
 * requests made (0 for a local store, which reads with pread, and for nodes already held).
 * Thread-safe; blocks until the requests are answered. */
size_t tp_store_prefetch(const tp_store* s, const int64_t* nodes, size_t count);
/* Reads node's stored bytes (tp_store_stored: not decoded) and checks them against their
 * CRC32, for tp_store_writer_add_stored. The bytes are the calling thread's, valid until its
 * next read of any store. TP_ERR_BAD_DATA / TP_ERR_IO as tp_store_read_node, naming the file,
 * the node and its byte offset. */
tp_status tp_store_read_stored(const tp_store* s, int64_t node, tp_store_stored* out,
                               tp_error* err);
/* The tree of an open store (tp_tree_create with the header's geometry, geotransform, height
 * step, quantisation error and error unit, and the store's metas): no node resident yet; attach
 * blocks read with tp_store_read_node. The tree borrows the store's metas: destroy it before
 * closing s. Fails as tp_tree_create (TP_ERR_OUT_OF_MEMORY; tp_store_open has checked the rest);
 * *out written only on success. */
tp_status tp_tree_create_from_store(const tp_store* s, tp_tree** out, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_STORE_H */
