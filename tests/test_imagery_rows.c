/*
 * test_imagery_rows.c - pyramids whose level 0 a caller makes (tp_imagery_build_rows,
 * io/src/imagery_rows.cpp and imagery_pyramid.cpp; tp_imagery.h, docs/imagery.md), and the
 * format's kinds and days:
 *   - a light map (TP_IMAGERY_KIND_LIGHT_TIMES) written and read back: its kind, day and maps,
 *     every level-0 block equal to what the rows gave (padding 0, a block never lit stored
 *     empty), every coarser texel tp_light_times_mean of the 2x2 below (not alpha-weighted),
 *     the callback asked for each row once, in order;
 *   - a version-1 pyramid (the fuzz seed crater_40x30.tpi) still opens, as imagery without a
 *     day;
 *   - a header whose kind is unknown, or whose day runs backward, is refused naming the file;
 *   - bad requests (a day of one map, an unknown kind, a light map at another texel shift) and
 *     a callback's failure write nothing.
 */
#define _GNU_SOURCE
#include "tp_imagery.h"
#include "tp_io.h"
#include "tp_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TP_TMP_PREFIX "tp_imagery_rows_"
#include "tp_test_tmp.h"

#define B TP_IMAGERY_BLOCK

/* A local-metres grid (no CRS) of w x h posts 30 m apart. */
static tp_imagery_target local_target(int w, int h)
{
    tp_imagery_target t;
    memset(&t, 0, sizeof t);
    t.crs_wkt = "";
    t.geotransform[0] = 500000.0, t.geotransform[1] = 30.0;
    t.geotransform[3] = 4700000.0, t.geotransform[5] = -30.0;
    t.width = w, t.height = h;
    return t;
}

/* The texels the rows give: a day's intervals r1 <= s1 <= r2 <= s2 from a seeded generator,
 * never lit (all 0) in the block (1, 0) and on a diagonal band, one interval elsewhere now and
 * then. */
static void texel_at(int x, int y, uint8_t t[4])
{
    tp_rng r = tp_rng_seed(((uint64_t)y << 32) ^ (uint64_t)x ^ 0x5eedull);
    if ((x / B == 1 && y / B == 0) || abs(x - y) < 3) {
        memset(t, 0, 4);
        return;
    }
    int v[4];
    for (int k = 0; k < 4; ++k)
        v[k] = tp_rng_int(&r, 0, 255);
    for (int i = 1; i < 4; ++i) /* sort */
        for (int j = i; j > 0 && v[j - 1] > v[j]; --j) {
            const int s = v[j];
            v[j] = v[j - 1], v[j - 1] = s;
        }
    if (tp_rng_int(&r, 0, 4) == 0)
        v[2] = v[3] = v[1];
    for (int k = 0; k < 4; ++k)
        t[k] = (uint8_t)v[k];
}

typedef struct rows_state {
    int width;
    int64_t next_row; /* the row the writer should ask for next */
    int calls, bad_order;
    int fail_at_row; /* >= 0: fail when asked for it */
} rows_state;

static tp_status give_rows(void* user, int64_t row0, int count, uint8_t* rgba, tp_error* err)
{
    rows_state* s = user;
    s->calls++;
    if (row0 != s->next_row || count < 1 || count > B)
        s->bad_order++;
    s->next_row = row0 + count;
    if (s->fail_at_row >= 0 && row0 <= s->fail_at_row && s->fail_at_row < row0 + count)
        return tp_error_set(err, TP_ERR_BAD_DATA, "the rows' own failure at row %d",
                            s->fail_at_row);
    for (int y = 0; y < count; ++y)
        for (int x = 0; x < s->width; ++x)
            texel_at(x, (int)row0 + y, rgba + 4 * ((size_t)y * s->width + x));
    return TP_OK;
}

static tp_imagery_rows light_rows(rows_state* s, int width)
{
    memset(s, 0, sizeof *s);
    s->width = width;
    s->fail_at_row = -1;
    tp_imagery_rows r;
    memset(&r, 0, sizeof r);
    r.kind = TP_IMAGERY_KIND_LIGHT_TIMES;
    r.time_first_s = 1782019004.0; /* 2026-06-21 04:16:44 UTC */
    r.time_last_s = 1782074097.0;
    r.maps = 64;
    r.notes = "a test light map";
    r.rows = give_rows;
    r.user = s;
    return r;
}

/* Level l's texels, whole, read block by block. */
static uint8_t* read_level(const tp_imagery* im, int l, int64_t* w, int64_t* h)
{
    int cols, rows;
    tp_imagery_level_size(im, l, w, h, &cols, &rows);
    uint8_t* img = calloc((size_t)cols * B * rows * B, 4);
    uint8_t* blk = malloc((size_t)B * B * 4);
    ASSERT_TRUE(img && blk);
    tp_error err;
    for (int by = 0; by < rows; ++by)
        for (int bx = 0; bx < cols; ++bx) {
            ASSERT_OK(tp_imagery_read_block(im, l, bx, by, blk, &err));
            for (int y = 0; y < B; ++y)
                memcpy(img + 4 * (((size_t)by * B + y) * cols * B + (size_t)bx * B),
                       blk + 4 * (size_t)y * B, 4 * (size_t)B);
        }
    free(blk);
    /* the texels beyond the level's size must be 0 */
    size_t beyond = 0;
    for (int64_t y = 0; y < (int64_t)rows * B; ++y)
        for (int64_t x = 0; x < (int64_t)cols * B; ++x)
            if (x >= *w || y >= *h)
                for (int c = 0; c < 4; ++c)
                    beyond += img[4 * ((size_t)y * cols * B + x) + c] != 0;
    EXPECT_EQ_INT(0, (int)beyond);
    /* packed to w texels a row */
    for (int64_t y = 0; y < *h; ++y)
        memmove(img + 4 * (size_t)(y * *w), img + 4 * (size_t)y * cols * B, 4 * (size_t)*w);
    return img;
}

TEST(light_map_round_trip_every_block_and_the_coarser_means)
{
    const char* dir = make_tmp_dir();
    char path[600];
    snprintf(path, sizeof path, "%s/day.tpl", dir);
    /* level 0: 3 x 2 blocks, level 1: 301 x 151 (2 x 1), level 2: 151 x 76: odd sizes, so the
     * last column and row of each coarser level have fewer than four texels below */
    const int W = 601, H = 301;
    tp_imagery_target t = local_target(W, H);
    rows_state s;
    tp_imagery_rows r = light_rows(&s, W);
    tp_error err;
    ASSERT_OK(tp_imagery_build_rows(&t, &r, NULL, path, &err));
    EXPECT_EQ_INT(0, s.bad_order);
    EXPECT_EQ_INT(2, s.calls); /* a block row at a time */
    EXPECT_EQ_INT(H, (int)s.next_row);

    tp_imagery* im = NULL;
    ASSERT_OK(tp_imagery_open(path, &im, &err));
    tp_imagery_info in;
    tp_imagery_get_info(im, &in);
    EXPECT_EQ_INT(TP_IMAGERY_KIND_LIGHT_TIMES, in.kind);
    EXPECT_EQ_DBL(r.time_first_s, in.time_first_s);
    EXPECT_EQ_DBL(r.time_last_s, in.time_last_s);
    EXPECT_EQ_INT(64, in.maps);
    EXPECT_EQ_INT(0, in.texel_shift);
    EXPECT_EQ_INT(3, in.levels);
    EXPECT_EQ_STR("a test light map", in.notes);
    EXPECT_EQ_INT(W, (int)in.width);
    EXPECT_EQ_INT(H, (int)in.height);
    EXPECT_TRUE(tp_imagery_block_is_empty(im, 0, 1, 0)); /* never lit: stored empty */
    EXPECT_FALSE(tp_imagery_block_is_empty(im, 0, 0, 0));

    int64_t w, h;
    uint8_t* l0 = read_level(im, 0, &w, &h);
    size_t differ = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            uint8_t e[4];
            texel_at(x, y, e);
            differ += memcmp(e, l0 + 4 * ((size_t)y * W + x), 4) != 0;
        }
    EXPECT_EQ_INT(0, (int)differ);
    uint8_t* fine = l0;
    int64_t fw = w, fh = h;
    for (int l = 1; l < in.levels; ++l) {
        uint8_t* coarse = read_level(im, l, &w, &h);
        EXPECT_EQ_INT((int)((fw + 1) / 2), (int)w);
        EXPECT_EQ_INT((int)((fh + 1) / 2), (int)h);
        size_t bad = 0, partial = 0;
        for (int64_t v = 0; v < h; ++v)
            for (int64_t u = 0; u < w; ++u) {
                const uint8_t* four[4];
                int n = 0;
                for (int j = 0; j < 2; ++j)
                    for (int i = 0; i < 2; ++i)
                        if (2 * u + i < fw && 2 * v + j < fh)
                            four[n++] = fine + 4 * ((size_t)(2 * v + j) * fw + 2 * u + i);
                partial += n < 4;
                uint8_t e[4];
                tp_light_times_mean(four, n, e);
                bad += memcmp(e, coarse + 4 * ((size_t)v * w + u), 4) != 0;
            }
        if (bad)
            FAIL("level %d: %zu of %lld texels are not the mean of the 2x2 below", l, bad,
                 (long long)(w * h));
        EXPECT_GT((double)partial, 0.0); /* the edge case ran */
        free(fine);
        fine = coarse, fw = w, fh = h;
    }
    free(fine);
    tp_imagery_close(im);
}

static uint32_t crc32_ref(const uint8_t* p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}
static uint32_t le32(const uint8_t* p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t le64(const uint8_t* p)
{
    return le32(p) | (uint64_t)le32(p + 4) << 32;
}
static void put32(uint8_t* p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

/* Every checksum of a pyramid of n bytes made to match its bytes (docs/imagery.md's layout):
 * the header's, each block's in the table, the table's, the footer's. */
static void fix_checksums(uint8_t* f, size_t n)
{
    const uint32_t hb = le32(f + 12);
    ASSERT_TRUE(hb >= 180 && hb <= n && n >= 40);
    put32(f + hb - 4, crc32_ref(f, hb - 4));
    uint8_t* foot = f + n - 40;
    const uint64_t table = le64(foot), table_bytes = le64(foot + 8);
    ASSERT_TRUE(table + table_bytes <= n - 40);
    for (uint64_t e = 0; e + 24 <= table_bytes; e += 24) {
        uint8_t* p = f + table + e;
        if (p[16] != 0 && le64(p) + le32(p + 8) <= n)
            put32(p + 12, crc32_ref(f + le64(p), le32(p + 8)));
    }
    put32(foot + 16, crc32_ref(f + table, (size_t)table_bytes));
    put32(foot + 24, crc32_ref(foot, 24));
}

/* The fuzz seed's first byte is the harness's switch; the rest a version-1 pyramid (whose
 * checksums the harness fixes: its notes were edited after it was written). */
TEST(version_1_pyramid_opens_as_imagery_without_a_day)
{
    FILE* f = fopen(TP_TEST_IMAGERY_V1_SEED, "rb");
    if (!f)
        SKIP("%s not found", TP_TEST_IMAGERY_V1_SEED);
    uint8_t* buf = malloc(1 << 20);
    ASSERT_TRUE(buf != NULL);
    const size_t n = fread(buf, 1, 1 << 20, f);
    fclose(f);
    ASSERT_GT((double)n, 200.0);
    EXPECT_EQ_INT(1, buf[1 + 8]); /* format version 1 */
    fix_checksums(buf + 1, n - 1);
    char path[600];
    snprintf(path, sizeof path, "%s/v1.tpi", make_tmp_dir());
    f = fopen(path, "wb");
    ASSERT_TRUE(f && fwrite(buf + 1, 1, n - 1, f) == n - 1);
    fclose(f);
    free(buf);
    tp_imagery* im = NULL;
    tp_error err;
    if (tp_imagery_open(path, &im, &err) != TP_OK)
        FAIL("a version-1 pyramid: %s", err.message);
    tp_imagery_info in;
    tp_imagery_get_info(im, &in);
    EXPECT_EQ_INT(TP_IMAGERY_KIND_IMAGE, in.kind);
    EXPECT_EQ_DBL(0.0, in.time_first_s);
    EXPECT_EQ_DBL(0.0, in.time_last_s);
    EXPECT_EQ_INT(0, in.maps);
    EXPECT_EQ_INT(40, in.grid_width);
    EXPECT_EQ_INT(30, in.grid_height);
    EXPECT_GT((double)in.nonempty_blocks, 0.0);
    uint8_t* blk = malloc((size_t)B * B * 4);
    ASSERT_OK(tp_imagery_read_block(im, 0, 0, 0, blk, &err));
    free(blk);
    tp_imagery_close(im);
}

/* Copies src to dst with `size` bytes at offset replaced by `bytes`, the header's CRC32 fixed
 * (docs/imagery.md: the header's last 4 bytes). */
static void patched_copy(const char* src, const char* dst, size_t offset, const void* bytes,
                         size_t size)
{
    FILE* f = fopen(src, "rb");
    ASSERT_TRUE(f != NULL);
    uint8_t* buf = malloc(8 << 20);
    ASSERT_TRUE(buf != NULL);
    const size_t n = fread(buf, 1, 8 << 20, f);
    fclose(f);
    memcpy(buf + offset, bytes, size);
    const uint32_t hb = le32(buf + 12);
    ASSERT_TRUE(hb >= 204 && hb <= n);
    put32(buf + hb - 4, crc32_ref(buf, hb - 4));
    f = fopen(dst, "wb");
    ASSERT_TRUE(f && fwrite(buf, 1, n, f) == n);
    fclose(f);
    free(buf);
}

TEST(unknown_kind_or_a_backward_day_is_refused_naming_the_file)
{
    const char* dir = make_tmp_dir();
    char good[600], bad[600];
    snprintf(good, sizeof good, "%s/good.tpl", dir);
    tp_imagery_target t = local_target(300, 200);
    rows_state s;
    tp_imagery_rows r = light_rows(&s, 300);
    tp_error err;
    ASSERT_OK(tp_imagery_build_rows(&t, &r, NULL, good, &err));
    tp_imagery* im = NULL;
    ASSERT_OK(tp_imagery_open(good, &im, &err)); /* the copies below differ only as patched */
    tp_imagery_close(im);
    im = NULL;

    snprintf(bad, sizeof bad, "%s/kind7.tpl", dir);
    uint8_t kind7[4] = {7, 0, 0, 0};
    patched_copy(good, bad, 36, kind7, 4); /* H_KIND */
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
    EXPECT_TRUE(im == NULL);
    EXPECT_CONTAINS(err.message, bad);
    EXPECT_CONTAINS(err.message, "unknown kind");

    snprintf(bad, sizeof bad, "%s/backward.tpl", dir);
    double first = r.time_last_s + 60.0; /* H_TIME_FIRST after the last */
    uint8_t le[8];
    uint64_t bits;
    memcpy(&bits, &first, 8);
    for (int i = 0; i < 8; ++i)
        le[i] = (uint8_t)(bits >> (8 * i));
    patched_copy(good, bad, 176, le, 8);
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
    EXPECT_CONTAINS(err.message, bad);
    EXPECT_CONTAINS(err.message, "day");

    snprintf(bad, sizeof bad, "%s/onemap.tpl", dir);
    uint8_t one[4] = {1, 0, 0, 0};
    patched_copy(good, bad, 192, one, 4); /* H_MAPS */
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
    EXPECT_CONTAINS(err.message, "fewer than 2 maps");

    snprintf(bad, sizeof bad, "%s/imagery_with_day.tpi", dir);
    uint8_t image[4] = {0, 0, 0, 0};
    patched_copy(good, bad, 36, image, 4);
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
    EXPECT_CONTAINS(err.message, "imagery with a day");
}

static int file_count(const char* dir)
{
    DIR* d = opendir(dir);
    int n = 0;
    for (struct dirent* e; d && (e = readdir(d)) != NULL;)
        n += e->d_name[0] != '.';
    if (d)
        closedir(d);
    return n;
}

TEST(bad_requests_and_failing_rows_write_nothing)
{
    const char* dir = make_tmp_dir();
    char path[600];
    snprintf(path, sizeof path, "%s/x.tpl", dir);
    tp_imagery_target t = local_target(300, 600);
    rows_state s;
    tp_error err;
    tp_imagery_rows r = light_rows(&s, 300);
    r.maps = 1;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_imagery_build_rows(&t, &r, NULL, path, &err));
    EXPECT_CONTAINS(err.message, "fewer than 2 maps");
    r = light_rows(&s, 300);
    r.time_last_s = r.time_first_s;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_imagery_build_rows(&t, &r, NULL, path, &err));
    r = light_rows(&s, 300);
    r.kind = 5;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_imagery_build_rows(&t, &r, NULL, path, &err));
    EXPECT_CONTAINS(err.message, "unknown kind");
    r = light_rows(&s, 300);
    r.texel_shift = 1;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_imagery_build_rows(&t, &r, NULL, path, &err));
    EXPECT_EQ_INT(0, s.calls);
    r = light_rows(&s, 300);
    s.fail_at_row = 300; /* the second block row */
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_build_rows(&t, &r, NULL, path, &err));
    EXPECT_CONTAINS(err.message, "the rows' own failure at row 300");
    EXPECT_EQ_INT(2, s.calls);
    EXPECT_EQ_INT(0, file_count(dir));
}

#define TESTS(X)                                                                                   \
    X(light_map_round_trip_every_block_and_the_coarser_means)                                      \
    X(version_1_pyramid_opens_as_imagery_without_a_day)                                            \
    X(unknown_kind_or_a_backward_day_is_refused_naming_the_file)                                   \
    X(bad_requests_and_failing_rows_write_nothing)

TP_TEST_MAIN(TESTS)
