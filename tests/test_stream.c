/* test_stream.c - app/scene/stream.c: the loader thread, the memory budget, substitution instead of
 * holes, and read failures, over a store written from a real DEM. */
#define _POSIX_C_SOURCE 200809L
#include "tp_core.h"
#include "tp_io.h"
#include "tp_test.h"

#include "stream.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define TP_TMP_PREFIX "tp_stream_"
#include "tp_test_tmp.h"

/* A store written from a crop of N42E001 (real relief and real SRTM voids), nodes of 17
 * samples so that the tree is deep. first: the node written first (its data starts right after
 * the header), or -1 for id order from the leaves up. */
typedef struct fixture {
    char path[600];
    tp_tree* full;    /* every node resident: the reference */
    tp_store* store;
    tp_tree* tree;    /* metas from the store, samples from the stream */
    float* heights;
    int w, h;
    double gt[6];
} fixture;

static void sleep_ms(int ms)
{
    struct timespec ts = {0, ms * 1000000L};
    nanosleep(&ts, NULL);
}

static int write_store(fixture* fx, int64_t first)
{
    tp_error err = {{0}};
    const tp_tree_geometry* g = tp_tree_get_geometry(fx->full);
    tp_tree_info ti;
    tp_tree_get_info(fx->full, &ti);
    tp_store_header hd;
    memset(&hd, 0, sizeof hd);
    hd.geometry = *g;
    memcpy(hd.geotransform, ti.geotransform, sizeof hd.geotransform);
    hd.height_step_m = ti.height_step_m;
    hd.quant_max_error_m = ti.quant_max_error_m;
    hd.err_unit_steps = ti.err_unit_steps;
    hd.crs_wkt = "";
    hd.notes = "test_stream";
    tp_store_writer* w;
    if (tp_store_writer_begin(fx->path, &hd, &w, &err) != TP_OK) {
        tp_test_note("%s", err.message);
        return 0;
    }
    size_t v = ((size_t)1 << g->n) + 1;
    int32_t* q = malloc(v * v * sizeof *q);
    for (int64_t k = -1; k < g->node_count; k++) {
        int64_t id = k < 0 ? first : g->node_count - 1 - k; /* leaves first, like the builder */
        if (id < 0 || (k >= 0 && id == first))
            continue;
        const uint16_t* s = tp_tree_samples(fx->full, id);
        const tp_node_meta* m = tp_tree_meta(fx->full, id);
        for (size_t i = 0; i < v * v; i++)
            q[i] = s[i] == TP_TREE_NO_HEIGHT ? INT32_MIN : (int32_t)s[i] + m->qmin;
        if (tp_store_writer_add_node(w, id, m, q, s + v * v, &err) != TP_OK) {
            tp_test_note("%s", err.message);
            free(q);
            tp_store_writer_abort(w);
            return 0;
        }
    }
    free(q);
    if (tp_store_writer_commit(w, &err) != TP_OK) {
        tp_test_note("%s", err.message);
        return 0;
    }
    return 1;
}

static int open_fixture(fixture* fx, int64_t first, int corrupt)
{
    memset(fx, 0, sizeof *fx);
    char dem_path[600];
    if (!tp_test_data_path(dem_path, sizeof dem_path, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
        return 0;
    tp_dem* dem = NULL;
    tp_error err = {{0}};
    if (tp_dem_read(dem_path, &dem, &err) != TP_OK) {
        tp_test_note("%s", err.message);
        return 0;
    }
    /* 385 x 289 samples from the middle of the tile; 90 m posts as a metric grid */
    fx->w = 385, fx->h = 289;
    fx->heights = malloc((size_t)fx->w * fx->h * sizeof *fx->heights);
    for (int y = 0; y < fx->h; y++)
        for (int x = 0; x < fx->w; x++)
            fx->heights[(size_t)y * fx->w + x] = dem->heights[(size_t)(400 + y) * dem->width + 300 + x];
    tp_dem_destroy(dem);
    const double gt[6] = {400000, 90, 0, 4700000, 0, -90};
    memcpy(fx->gt, gt, sizeof gt);
    if (tp_tree_create_from_grid(fx->heights, (size_t)fx->w * fx->h, fx->w, fx->h, gt, 17, 0,
                                 &fx->full, &err) != TP_OK) {
        tp_test_note("%s", err.message);
        return 0;
    }
    snprintf(fx->path, sizeof fx->path, "%s/stream.tpt", make_tmp_dir());
    if (!write_store(fx, first))
        return 0;
    if (corrupt) {
        /* a byte inside the first node's data, which starts right after the location table
         * (docs/store.md: its offset and size are u64s at 16 and 24 in the 56-byte footer) */
        int fd = open(fx->path, O_RDWR);
        struct stat sb;
        uint8_t foot[56];
        if (fd < 0 || fstat(fd, &sb) != 0 || pread(fd, foot, 56, sb.st_size - 56) != 56)
            return 0;
        uint64_t data_offset = 0;
        for (int k = 7; k >= 0; k--)
            data_offset = data_offset << 8 | foot[16 + k];
        uint64_t loc_bytes = 0;
        for (int k = 7; k >= 0; k--)
            loc_bytes = loc_bytes << 8 | foot[24 + k];
        data_offset += loc_bytes;
        uint8_t b;
        if (pread(fd, &b, 1, (off_t)data_offset + 4) != 1)
            return 0;
        b ^= 0x5A;
        if (pwrite(fd, &b, 1, (off_t)data_offset + 4) != 1)
            return 0;
        close(fd);
    }
    if (tp_store_open(fx->path, &fx->store, &err) != TP_OK) {
        tp_test_note("%s", err.message);
        return 0;
    }
    if (tp_tree_create_from_store(fx->store, &fx->tree, &err) != TP_OK) {
        tp_test_note("%s", err.message);
        return 0;
    }
    return 1;
}

static void close_fixture(fixture* fx)
{
    tp_tree_destroy(fx->tree);
    tp_store_close(fx->store);
    tp_tree_destroy(fx->full);
    free(fx->heights);
    unlink(fx->path);
}

/* A camera 300 m above the ground at grid (x, y), looking along yaw, 20 degrees down. */
static void camera_at(const fixture* fx, double x, double y, double yaw, tp_camera* cam)
{
    double e = fx->gt[0] + (x + 0.5) * fx->gt[1], n = fx->gt[3] + (y + 0.5) * fx->gt[5];
    double z = tp_tree_sample(fx->full, (int)x, (int)y);
    double pos[3] = {e, n, (isnan(z) ? 1500 : z) + 300};
    tp_camera_from_pose(pos, yaw, -20, 60, 640, 360, cam);
}

/* Leaves (by leaf column and row) covered by the drawn nodes of a cut, as a bitmap. */
static void covered_leaves(const tp_tree* t, const tp_cut* c, uint8_t* bits)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    memset(bits, 0, (size_t)g->cols * g->rows);
    size_t count;
    const tp_cut_node* nodes = tp_cut_nodes(c, &count);
    for (size_t i = 0; i < count; i++) {
        int s, col, row;
        tp_tree_node_locate(g, nodes[i].node, &s, &col, &row);
        for (int r = row << s; r < (row + 1) << s; r++)
            for (int q = col << s; q < (col + 1) << s; q++)
                bits[(size_t)r * g->cols + q] = 1;
    }
}

/* Runs frames at cam until nothing is pending and the cut asks for nothing (or max_ms). */
static int settle(fixture* fx, tp_stream* st, tp_cut* cut, const tp_camera* cam, int max_ms)
{
    tp_error err;
    tp_stream_stats ss;
    for (int waited = 0; waited < max_ms; waited += 2) {
        if (tp_cut_update(cut, cam, NULL, &err) != TP_OK)
            return 0;
        tp_stream_frame(st, cut, NULL, cam, NULL, &ss);
        size_t nreq;
        tp_cut_requests(cut, &nreq);
        if (ss.pending == 0 && nreq == 0)
            return 1;
        sleep_ms(2);
    }
    (void)fx;
    return 0;
}

TEST(roots_first_then_the_view_fills_in_without_holes)
{
    fixture fx;
    ASSERT_TRUE(open_fixture(&fx, -1, 0));
    tp_error err = {{0}};
    tp_stream_options o = {.memory_bytes = 64u << 20};
    tp_stream* st = tp_stream_create(fx.store, fx.tree, &o, &err);
    if (!st)
        tp_test_note("%s", err.message);
    ASSERT_TRUE(st != NULL);
    const tp_tree_geometry* g = tp_tree_get_geometry(fx.tree);
    tp_stream_stats ss;
    tp_stream_get_stats(st, &ss);
    EXPECT_EQ_INT(ss.resident_nodes, g->root_count);

    tp_cut *cut = NULL, *ref = NULL;
    ASSERT_OK(tp_cut_create(fx.tree, &cut, &err));
    ASSERT_OK(tp_cut_create(fx.full, &ref, &err));
    tp_camera cam;
    camera_at(&fx, 120, 200, 45, &cam);
    /* The first frame: only the roots, so everything drawn is a substitute, and the view's
     * leaves are all covered all the same (no hole). */
    ASSERT_OK(tp_cut_update(cut, &cam, NULL, &err));
    ASSERT_OK(tp_cut_update(ref, &cam, NULL, &err));
    uint8_t* a = malloc((size_t)g->cols * g->rows);
    uint8_t* b = malloc((size_t)g->cols * g->rows);
    covered_leaves(fx.tree, cut, a);
    covered_leaves(fx.full, ref, b);
    size_t holes = 0;
    for (size_t i = 0; i < (size_t)g->cols * g->rows; i++)
        holes += b[i] && !a[i];
    EXPECT_EQ_INT(holes, 0);
    tp_cut_stats cs;
    tp_cut_get_stats(cut, &cs);
    EXPECT_TRUE(cs.substituted > 0);
    EXPECT_TRUE(cs.requests > 0);

    /* Then the loader fills in the view: the cut becomes the fully resident one. */
    ASSERT_TRUE(settle(&fx, st, cut, &cam, 10000));
    tp_cut_get_stats(cut, &cs);
    EXPECT_EQ_INT(cs.substituted, 0);
    size_t n1, n2;
    const tp_cut_node* x1 = tp_cut_nodes(cut, &n1);
    const tp_cut_node* x2 = tp_cut_nodes(ref, &n2);
    ASSERT_EQ_INT(n1, n2);
    size_t differ = 0;
    for (size_t i = 0; i < n1; i++)
        differ += x1[i].node != x2[i].node || x1[i].level != x2[i].level;
    EXPECT_EQ_INT(differ, 0);
    /* and the streamed samples are the store's: the drawn surface is the same */
    size_t bad = 0;
    for (int y = 0; y < fx.h; y += 7)
        for (int x = 0; x < fx.w; x += 7) {
            double p = tp_cut_drawn_height_at(cut, x, y), q = tp_cut_drawn_height_at(ref, x, y);
            bad += !(p == q || (isnan(p) && isnan(q)));
        }
    EXPECT_EQ_INT(bad, 0);
    tp_stream_get_stats(st, &ss);
    tp_test_note("%zu nodes resident (%.1f MB) of %lld after settling", ss.resident_nodes,
                 ss.resident_bytes / 1e6, (long long)g->node_count);
    EXPECT_TRUE(ss.resident_nodes < (size_t)g->node_count);
    free(a);
    free(b);
    tp_cut_destroy(cut);
    tp_cut_destroy(ref);
    tp_stream_destroy(st);
    close_fixture(&fx);
}

TEST(budget_is_honoured_along_a_flight_and_nothing_is_ever_a_hole)
{
    fixture fx;
    ASSERT_TRUE(open_fixture(&fx, -1, 0));
    const tp_tree_geometry* g = tp_tree_get_geometry(fx.tree);
    size_t block = (((size_t)1 << g->n) + 1) * (((size_t)1 << g->n) + 1) * 2;
    /* room for the roots and 150 more nodes: far less than the flight touches */
    size_t budget = ((size_t)g->root_count + 150) * block;
    tp_error err = {{0}};
    tp_stream_options o = {.memory_bytes = budget};
    tp_stream* st = tp_stream_create(fx.store, fx.tree, &o, &err);
    ASSERT_TRUE(st != NULL);
    tp_cut *cut = NULL, *ref = NULL, *pre = NULL;
    ASSERT_OK(tp_cut_create(fx.tree, &cut, &err));
    ASSERT_OK(tp_cut_create(fx.tree, &pre, &err));
    ASSERT_OK(tp_cut_create(fx.full, &ref, &err));
    uint8_t* a = malloc((size_t)g->cols * g->rows);
    uint8_t* b = malloc((size_t)g->cols * g->rows);
    size_t max_resident = 0, holes = 0, released = 0, substituted_frames = 0;
    const int frames = 300;
    for (int i = 0; i < frames; i++) {
        /* west to east and back along the crop, low */
        double t = (double)i / (frames - 1), x = 20 + (fx.w - 40) * (t < 0.5 ? 2 * t : 2 - 2 * t);
        tp_camera cam;
        camera_at(&fx, x, fx.h / 2.0, t < 0.5 ? 90 : 270, &cam);
        ASSERT_OK(tp_cut_update(cut, &cam, NULL, &err));
        tp_stream_stats ss;
        tp_stream_frame(st, cut, pre, &cam, NULL, &ss);
        ASSERT_OK(tp_cut_update(ref, &cam, NULL, &err));
        covered_leaves(fx.tree, cut, a);
        covered_leaves(fx.full, ref, b);
        for (size_t k = 0; k < (size_t)g->cols * g->rows; k++)
            holes += b[k] && !a[k];
        max_resident = ss.resident_bytes > max_resident ? ss.resident_bytes : max_resident;
        released += (size_t)ss.released;
        tp_cut_stats cs;
        tp_cut_get_stats(cut, &cs);
        substituted_frames += cs.substituted > 0;
        sleep_ms(1);
    }
    tp_test_note("budget %.2f MB: at most %.2f MB resident, %zu nodes released, %zu of %d "
                 "frames with substitutes",
                 budget / 1e6, max_resident / 1e6, released, substituted_frames, frames);
    EXPECT_EQ_INT(holes, 0);
    EXPECT_TRUE(max_resident <= budget);
    EXPECT_TRUE(released > 0); /* the flight needed more than the budget: it had to release */
    free(a);
    free(b);
    tp_cut_destroy(cut);
    tp_cut_destroy(pre);
    tp_cut_destroy(ref);
    tp_stream_destroy(st);
    close_fixture(&fx);
}

TEST(a_damaged_node_is_reported_once_and_its_ancestor_drawn)
{
    fixture fx;
    /* the leaf under the camera is written first; a byte of its data is then damaged */
    ASSERT_TRUE(open_fixture(&fx, -1, 0));
    /* a copy: the fixture's trees go with close_fixture */
    const tp_tree_geometry geometry = *tp_tree_get_geometry(fx.full), *g = &geometry;
    int64_t leaf = tp_tree_node_id(g, 0, 7, 10);
    close_fixture(&fx);
    ASSERT_TRUE(open_fixture(&fx, leaf, 1));
    tp_error err = {{0}};
    tp_stream* st = tp_stream_create(fx.store, fx.tree, NULL, &err);
    ASSERT_TRUE(st != NULL);
    tp_cut* cut = NULL;
    ASSERT_OK(tp_cut_create(fx.tree, &cut, &err));
    tp_camera cam;
    /* right above that leaf (17-sample leaves: column 7 is x = 112 .. 128), looking down */
    double e = fx.gt[0] + 120.5 * fx.gt[1], n = fx.gt[3] + 168.5 * fx.gt[5];
    double pos[3] = {e, n, 3200};
    tp_camera_from_pose(pos, 0, -89, 60, 640, 360, &cam);
    for (int i = 0; i < 2000; i++) {
        ASSERT_OK(tp_cut_update(cut, &cam, NULL, &err));
        tp_stream_stats ss;
        tp_stream_frame(st, cut, NULL, &cam, NULL, &ss);
        if (ss.failed && ss.pending == 0)
            break;
        sleep_ms(2);
    }
    const char* f = tp_stream_take_failure(st);
    ASSERT_TRUE(f != NULL);
    tp_test_note("reported: %s", f);
    EXPECT_TRUE(strstr(f, "stream.tpt") != NULL);
    EXPECT_TRUE(strstr(f, "node") != NULL);
    EXPECT_TRUE(tp_stream_take_failure(st) == NULL); /* once */
    /* the leaf is never drawn; what covers it is a substitute, and there is no hole there */
    ASSERT_OK(tp_cut_update(cut, &cam, NULL, &err));
    size_t count;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    int leaf_drawn = 0, covered = 0;
    for (size_t i = 0; i < count; i++) {
        int s, c, r;
        tp_tree_node_locate(g, nodes[i].node, &s, &c, &r);
        leaf_drawn |= nodes[i].node == leaf;
        covered |= (7 >> s) == c && (10 >> s) == r;
    }
    EXPECT_FALSE(leaf_drawn);
    EXPECT_TRUE(covered);
    tp_cut_destroy(cut);
    tp_stream_destroy(st);
    close_fixture(&fx);
}

TEST(require_loads_a_node_and_its_ancestors_now)
{
    fixture fx;
    ASSERT_TRUE(open_fixture(&fx, -1, 0));
    tp_error err = {{0}};
    tp_stream_options o = {.no_loader = 1};
    tp_stream* st = tp_stream_create(fx.store, fx.tree, &o, &err);
    ASSERT_TRUE(st != NULL);
    const tp_tree_geometry* g = tp_tree_get_geometry(fx.tree);
    int64_t leaf = tp_tree_node_id(g, 0, 3, 5);
    EXPECT_TRUE(tp_tree_samples(fx.tree, leaf) == NULL);
    ASSERT_TRUE(tp_stream_require(st, leaf, &err));
    for (int64_t id = leaf; id >= 0; id = tp_tree_node_parent(g, id)) {
        const uint16_t* s = tp_tree_samples(fx.tree, id);
        ASSERT_TRUE(s != NULL);
        size_t v = ((size_t)1 << g->n) + 1;
        EXPECT_TRUE(memcmp(s, tp_tree_samples(fx.full, id), v * v * 2) == 0);
    }
    /* full resolution there: the height query answers as the resident tree does */
    for (int y = 5 * 16; y <= 6 * 16; y++)
        for (int x = 3 * 16; x <= 4 * 16; x++) {
            double p = tp_tree_sample(fx.tree, x, y), q = tp_tree_sample(fx.full, x, y);
            ASSERT_TRUE(p == q || (isnan(p) && isnan(q)));
        }
    tp_stream_destroy(st);
    close_fixture(&fx);
}

/* Requests of cut a not among cut b's, not resident, into out (at most cap); their count. */
static size_t requests_not_in(const tp_tree* t, const tp_cut* a, const tp_cut* b, int64_t* out,
                              size_t cap)
{
    size_t na, nb, k = 0;
    const int64_t* ra = tp_cut_requests(a, &na);
    const int64_t* rb = tp_cut_requests(b, &nb);
    for (size_t i = 0; i < na && k < cap; i++) {
        int found = 0;
        for (size_t j = 0; j < nb && !found; j++)
            found = ra[i] == rb[j];
        if (!found && !tp_tree_samples(t, ra[i]))
            out[k++] = ra[i];
    }
    return k;
}

/* A flight east along the crop's middle row at 270 m/s on a 30 Hz clock, looking 5 s ahead
 * (1350 m: 15 samples, about a leaf), every node above the leaves resident so that the cuts
 * ask for leaves. */
static tp_stream* prefetch_fixture(fixture* fx, int loader)
{
    tp_error err = {{0}};
    tp_stream_options o = {.no_loader = !loader, .frame_s = 1.0 / 30, .prefetch_s = 5};
    tp_stream* st = tp_stream_create(fx->store, fx->tree, &o, &err);
    if (!st)
        return NULL;
    const tp_tree_geometry* g = tp_tree_get_geometry(fx->tree);
    for (int64_t id = 0; id < g->node_count; id++) {
        int s, c, r;
        tp_tree_node_locate(g, id, &s, &c, &r);
        if (s > 0 && !tp_stream_require(st, id, &err)) {
            tp_test_note("%s", err.message);
            tp_stream_destroy(st);
            return NULL;
        }
    }
    return st;
}

TEST(prefetch_requests_stay_queued_between_prefetch_updates)
{
    fixture fx;
    ASSERT_TRUE(open_fixture(&fx, -1, 0));
    tp_stream* st = prefetch_fixture(&fx, 0);
    ASSERT_TRUE(st != NULL);
    tp_cut *cut = NULL, *pre = NULL;
    tp_error err;
    ASSERT_OK(tp_cut_create(fx.tree, &cut, &err));
    ASSERT_OK(tp_cut_create(fx.tree, &pre, &err));
    int64_t ahead[256];
    size_t nahead = 0, checked = 0, missing = 0;
    int updates = 0;
    const int frames = 120;
    for (int i = 0; i < frames; i++) {
        tp_camera cam;
        camera_at(&fx, 20 + 0.1 * i, fx.h / 2.0, 90, &cam); /* 9 m per frame */
        ASSERT_OK(tp_cut_update(cut, &cam, NULL, &err));
        tp_stream_stats ss;
        tp_stream_frame(st, cut, pre, &cam, NULL, &ss);
        if (ss.prefetch_updated) {
            updates++;
            nahead = requests_not_in(fx.tree, pre, cut, ahead, 256);
            continue;
        }
        /* between updates: what the prefetch asked for is still waiting for the loader */
        for (size_t k = 0; k < nahead; k++, checked++)
            missing += !tp_stream_is_queued(st, ahead[k]);
    }
    tp_test_note("%d prefetch updates in %d frames; %zu checks of prefetch-only requests "
                 "between updates, %zu not queued", updates, frames, checked, missing);
    /* straight flight at 30 Hz: the prefetch cut is selected every 4th frame or so */
    EXPECT_TRUE(updates >= frames / 6 && updates <= frames / 3);
    EXPECT_TRUE(checked > 0);
    EXPECT_EQ_INT(missing, 0);
    tp_cut_destroy(cut);
    tp_cut_destroy(pre);
    tp_stream_destroy(st);
    close_fixture(&fx);
}

TEST(a_prefetch_request_is_served_before_the_cut_asks_for_it)
{
    fixture fx;
    ASSERT_TRUE(open_fixture(&fx, -1, 0));
    tp_stream* st = prefetch_fixture(&fx, 1);
    ASSERT_TRUE(st != NULL);
    tp_cut *cut = NULL, *pre = NULL;
    tp_error err;
    ASSERT_OK(tp_cut_create(fx.tree, &cut, &err));
    ASSERT_OK(tp_cut_create(fx.tree, &pre, &err));
    tp_camera cam;
    camera_at(&fx, 20, fx.h / 2.0, 90, &cam);
    ASSERT_TRUE(settle(&fx, st, cut, &cam, 5000));
    int64_t ahead[4096];
    size_t nahead = 0;
    for (int i = 0; i < 120; i++) {
        camera_at(&fx, 20 + 0.1 * i, fx.h / 2.0, 90, &cam);
        ASSERT_OK(tp_cut_update(cut, &cam, NULL, &err));
        tp_stream_stats ss;
        tp_stream_frame(st, cut, pre, &cam, NULL, &ss);
        if (ss.prefetch_updated && nahead < 4096)
            nahead += requests_not_in(fx.tree, pre, cut, ahead + nahead, 4096 - nahead);
        sleep_ms(1);
    }
    /* every node only the prefetch asked for arrives (none is released: no budget), with the
       camera standing at the flight's end: a loaded machine may need more than the flight's
       120 ms, so frames go on (at most 10 s) until it has */
    size_t served = 0;
    int extra = 0;
    for (; extra < 10000; extra++) {
        served = 0;
        for (size_t k = 0; k < nahead; k++)
            served += tp_tree_samples(fx.tree, ahead[k]) != NULL;
        if (served == nahead)
            break;
        ASSERT_OK(tp_cut_update(cut, &cam, NULL, &err));
        tp_stream_stats ss;
        tp_stream_frame(st, cut, pre, &cam, NULL, &ss);
        sleep_ms(1);
    }
    tp_test_note("%zu of %zu prefetch-only requests resident (%d frames after the flight)",
                 served, nahead, extra);
    EXPECT_TRUE(nahead > 0);
    EXPECT_EQ_INT(served, nahead);
    tp_cut_destroy(cut);
    tp_cut_destroy(pre);
    tp_stream_destroy(st);
    close_fixture(&fx);
}

#define TESTS(X)                                                                                   \
    X(roots_first_then_the_view_fills_in_without_holes)                                            \
    X(budget_is_honoured_along_a_flight_and_nothing_is_ever_a_hole)                                \
    X(a_damaged_node_is_reported_once_and_its_ancestor_drawn)                                      \
    X(require_loads_a_node_and_its_ancestors_now)                                                  \
    X(prefetch_requests_stay_queued_between_prefetch_updates)                                      \
    X(a_prefetch_request_is_served_before_the_cut_asks_for_it)
TP_TEST_MAIN(TESTS)
