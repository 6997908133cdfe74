/*
 * store_merge.h - the parts of a build in parts (`terrapatch build --part I/N`, build_part.h)
 * joined into the store one build of the same sources and options writes, byte for byte
 * (store_merge.c), for `terrapatch merge` (commands/cmd_merge.c).
 *
 * Every part is checked before a byte is written: a store, a part's record in its notes, the
 * same split, sources and options as the others (its key), each part once, none missing, its
 * strip the one its record names. The nodes above the split scale are computed from the parts'
 * split-scale nodes (their samples, masks, filled bits and metas: tp_tree_node_from_children,
 * as the band builder computes them); every other node is copied as stored (checked against
 * its CRC32), in the order one build writes them, so the file is the one build's.
 */
#ifndef TP_APP_STORE_MERGE_H
#define TP_APP_STORE_MERGE_H

#include <stddef.h>
#include <stdint.h>

typedef struct tp_merge_options {
    const char** parts; /* part_count paths of parts, any order */
    int part_count;
    const char* out;    /* MAP.tpt */
    int quiet;          /* no notes or progress on stderr */
} tp_merge_options;

typedef struct tp_merge_result {
    int width, height, parts, split_scale;
    int64_t nodes, copied, computed; /* computed: the nodes above the parts */
    uint64_t bytes;
    double check_seconds, above_seconds, seconds, rss_peak_mb;
} tp_merge_result;

/* Writes o->out from the parts (atomically: nothing on failure). Returns an exit code
 * (base/cli.h) after one line on stderr naming the part and what is wrong (a part missing,
 * given twice, of other sources or options or another split, damaged: TP_EXIT_FAILURE),
 * 128 + the signal after SIGINT/SIGTERM; *result (may be NULL) set on TP_EXIT_OK. */
int tp_store_merge(const tp_merge_options* o, tp_merge_result* result);

#endif /* TP_APP_STORE_MERGE_H */
