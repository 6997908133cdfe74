/*
 * test_bad_input.c - tp_dem_read on bad input: each kind of bad file gets its own test, which
 * checks the specific tp_status, that the message names the file, and that the out-parameter
 * is left alone (STYLE.md section 4 and 8). A few neighbours of bad input that must still be
 * read (infinite heights among valid ones, bottom-up rows, a global grid with posts on the
 * poles) are tested here too, so that the refusals stay narrow.
 *
 * Every file is built by hand at test time in a fresh mkdtemp directory and removed afterwards:
 * GeoTIFFs by a small TIFF writer below (header, then the IFD, then tag data, then the image,
 * so that a cut in the image leaves the IFD whole), ESRI ASCII grids and VRT XML as text, PNGs
 * chunk by chunk (stored deflate blocks, CRCs computed here), FIFOs with mkfifo. Heightmap
 * images (by extension, as `terrapatch` chooses) go through tp_dem_read_image, the rest through
 * tp_dem_read. Damaged copies of real files (a DTED tile, an ESRI ASCII grid) are made from
 * data/ at test time.
 *
 * `test_bad_input --write-files DIR` writes the file of each case into DIR instead of running
 * tests: tests/CMakeLists.txt runs it as a ctest fixture, then `terrapatch info` on each file
 * (the cli.bad_input.* tests: exit status 1 and one stderr line naming the file).
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---------------------------------------------------------------------------------------------
 * Writing files. These return 1 on success and 0 on failure (never ASSERT: --write-files runs
 * them outside a test).
 */
static int write_bytes(const char* path, const void* data, size_t size)
{
    FILE* f = fopen(path, "wb");
    int ok;
    if (!f)
        return 0;
    ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok;
}

static int write_text(const char* path, const char* text)
{
    return write_bytes(path, text, strlen(text));
}

/* A growing little-endian byte buffer. */
typedef struct bytes {
    unsigned char* p;
    size_t size, cap;
    int failed;
} bytes;

static void put(bytes* b, const void* data, size_t n)
{
    if (b->failed)
        return;
    if (b->size + n > b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 1024;
        unsigned char* p;
        while (cap < b->size + n)
            cap *= 2;
        p = (unsigned char*)realloc(b->p, cap);
        if (!p) {
            b->failed = 1;
            return;
        }
        b->p = p;
        b->cap = cap;
    }
    memcpy(b->p + b->size, data, n);
    b->size += n;
}
static void put_u16(bytes* b, unsigned v)
{
    unsigned char c[2] = {(unsigned char)(v & 0xff), (unsigned char)(v >> 8 & 0xff)};
    put(b, c, 2);
}
static void put_u32(bytes* b, uint32_t v)
{
    unsigned char c[4] = {(unsigned char)(v & 0xff), (unsigned char)(v >> 8 & 0xff),
                          (unsigned char)(v >> 16 & 0xff), (unsigned char)(v >> 24 & 0xff)};
    put(b, c, 4);
}
static void put_f64(bytes* b, double v)
{
    uint64_t u;
    int i;
    memcpy(&u, &v, sizeof u);
    for (i = 0; i < 8; ++i) {
        unsigned char c = (unsigned char)(u >> (8 * i) & 0xff);
        put(b, &c, 1);
    }
}

/* A single-band GeoTIFF, uncompressed, little-endian. */
typedef struct tiff_spec {
    int width, height;
    int float32;        /* 1: Float32 samples (data is float*), 0: Int16 (data is int16_t*) */
    const void* data;   /* width * height samples, row 0 first; NULL: zeros */
    int rows_per_strip; /* striped layout (0: one strip) */
    int tile;           /* > 0: tiled, tile x tile (a multiple of 16) instead of strips */
    const double* gt;   /* GDAL geotransform, written as ModelTransformation; NULL: none */
    int geographic;     /* 1: EPSG:4326 GeoKeys, 0: none */
    const char* nodata; /* GDAL_NODATA tag, NULL: none */
} tiff_spec;

typedef struct tiff_entry {
    unsigned tag, type;
    uint32_t count;
    uint32_t value;   /* inline value (SHORT or LONG), when data is NULL */
    const void* data; /* out of line: raw little-endian bytes */
    size_t data_size;
} tiff_entry;

enum { T_SHORT = 3, T_LONG = 4, T_ASCII = 2, T_DOUBLE = 12 };

/* Builds the file in memory (free *out when done). Layout: header, IFD, out-of-line tag data,
 * then the image blocks in order: cutting the file anywhere in the image keeps the IFD whole. */
static int tiff_build(const tiff_spec* sp, unsigned char** out, size_t* out_size)
{
    const int bps = sp->float32 ? 4 : 2;
    const int bw = sp->tile ? sp->tile : sp->width;
    const int strip_rows =
        sp->rows_per_strip > 0 && sp->rows_per_strip < sp->height ? sp->rows_per_strip : sp->height;
    const int rps = sp->tile ? sp->tile : strip_rows; /* rows per block */
    const int across = (sp->width + bw - 1) / bw, down = (sp->height + rps - 1) / rps;
    const int nblocks = across * down;
    const size_t block_bytes = (size_t)bw * (size_t)rps * (size_t)bps;
    bytes offsets = {0}, counts = {0}, matrix = {0}, keys = {0}, img = {0};
    tiff_entry e[20];
    int n = 0, i, bx, by, x, y, ok;
    bytes file = {0};
    size_t ifd_size, data_at, image_at;

    /* image blocks: edge blocks are padded to full size, as TIFF stores them */
    for (by = 0; by < down; ++by)
        for (bx = 0; bx < across; ++bx)
            for (y = 0; y < rps; ++y)
                for (x = 0; x < bw; ++x) {
                    int gx = bx * bw + x, gy = by * rps + y;
                    size_t k = (size_t)gy * (size_t)sp->width + (size_t)gx;
                    int inside = gx < sp->width && gy < sp->height;
                    if (sp->float32) {
                        float v = inside && sp->data ? ((const float*)sp->data)[k] : 0.0f;
                        uint32_t u;
                        memcpy(&u, &v, sizeof u);
                        put_u32(&img, u);
                    } else {
                        int16_t v = inside && sp->data ? ((const int16_t*)sp->data)[k] : 0;
                        put_u16(&img, (unsigned)(uint16_t)v);
                    }
                }
    if (sp->gt) {
        const double* g = sp->gt;
        const double m[16] = {g[1], g[2], 0, g[0], g[4], g[5], 0, g[3], 0, 0, 0, 0, 0, 0, 0, 1};
        for (i = 0; i < 16; ++i)
            put_f64(&matrix, m[i]);
    }
    if (sp->geographic) {
        /* version 1.1.0, 3 keys: model type geographic, raster type pixel-is-area, EPSG:4326 */
        const unsigned k[16] = {1, 1, 0, 3, 1024, 0, 1, 2, 1025, 0, 1, 1, 2048, 0, 1, 4326};
        for (i = 0; i < 16; ++i)
            put_u16(&keys, k[i]);
    }

#define ENTRY(t, ty, c, v, d, ds) (e[n++] = (tiff_entry){(t), (ty), (uint32_t)(c), (v), (d), (ds)})
    ENTRY(256, T_LONG, 1, (uint32_t)sp->width, NULL, 0);
    ENTRY(257, T_LONG, 1, (uint32_t)sp->height, NULL, 0);
    ENTRY(258, T_SHORT, 1, (uint32_t)(bps * 8), NULL, 0);
    ENTRY(259, T_SHORT, 1, 1, NULL, 0); /* no compression */
    ENTRY(262, T_SHORT, 1, 1, NULL, 0); /* min-is-black */
    if (!sp->tile)
        ENTRY(273, T_LONG, nblocks, 0, NULL, 0); /* strip offsets: filled in below */
    ENTRY(277, T_SHORT, 1, 1, NULL, 0);
    if (!sp->tile) {
        ENTRY(278, T_LONG, 1, (uint32_t)rps, NULL, 0);
        ENTRY(279, T_LONG, nblocks, 0, NULL, 0); /* strip byte counts */
    }
    ENTRY(284, T_SHORT, 1, 1, NULL, 0); /* contiguous */
    if (sp->tile) {
        ENTRY(322, T_LONG, 1, (uint32_t)sp->tile, NULL, 0);
        ENTRY(323, T_LONG, 1, (uint32_t)sp->tile, NULL, 0);
        ENTRY(324, T_LONG, nblocks, 0, NULL, 0);
        ENTRY(325, T_LONG, nblocks, 0, NULL, 0);
    }
    ENTRY(339, T_SHORT, 1, sp->float32 ? 3 : 2, NULL, 0); /* IEEE float / signed int */
    if (sp->gt)
        ENTRY(34264, T_DOUBLE, 16, 0, matrix.p, matrix.size);
    if (sp->geographic)
        ENTRY(34735, T_SHORT, 16, 0, keys.p, keys.size);
    if (sp->nodata)
        ENTRY(42113, T_ASCII, strlen(sp->nodata) + 1, 0, sp->nodata, strlen(sp->nodata) + 1);
#undef ENTRY

    /* offsets: header 8, IFD, then each out-of-line value (word aligned), then the image */
    ifd_size = 2 + 12 * (size_t)n + 4;
    data_at = 8 + ifd_size;
    image_at = data_at;
    for (i = 0; i < n; ++i) {
        int is_block_list =
            e[i].tag == 273 || e[i].tag == 279 || e[i].tag == 324 || e[i].tag == 325;
        if (is_block_list && nblocks > 1)
            image_at += 4 * (size_t)nblocks;
        else if (e[i].data && e[i].data_size > 4)
            image_at += (e[i].data_size + 1) & ~(size_t)1;
    }
    for (i = 0; i < nblocks; ++i) {
        put_u32(&offsets, (uint32_t)(image_at + (size_t)i * block_bytes));
        put_u32(&counts, (uint32_t)block_bytes);
    }
    for (i = 0; i < n; ++i) {
        if (e[i].tag == 273 || e[i].tag == 324) {
            e[i].data = offsets.p;
            e[i].data_size = offsets.size;
        } else if (e[i].tag == 279 || e[i].tag == 325) {
            e[i].data = counts.p;
            e[i].data_size = counts.size;
        }
    }

    put(&file, "II*\0", 4);
    put_u32(&file, 8);
    put_u16(&file, (unsigned)n);
    {
        size_t at = data_at;
        for (i = 0; i < n; ++i) {
            put_u16(&file, e[i].tag);
            put_u16(&file, e[i].type);
            put_u32(&file, e[i].count);
            if (e[i].data && e[i].data_size > 4) {
                put_u32(&file, (uint32_t)at);
                at += (e[i].data_size + 1) & ~(size_t)1;
            } else if (e[i].data) {
                unsigned char word[4] = {0, 0, 0, 0};
                memcpy(word, e[i].data, e[i].data_size);
                put(&file, word, 4);
            } else if (e[i].type == T_SHORT) {
                put_u16(&file, e[i].value);
                put_u16(&file, 0);
            } else {
                put_u32(&file, e[i].value);
            }
        }
    }
    put_u32(&file, 0); /* no next IFD */
    for (i = 0; i < n; ++i)
        if (e[i].data && e[i].data_size > 4) {
            put(&file, e[i].data, e[i].data_size);
            if (e[i].data_size & 1)
                put(&file, "", 1);
        }
    ok = !file.failed && file.size == image_at;
    put(&file, img.p, img.size);
    ok = ok && !file.failed && !offsets.failed && !counts.failed && !matrix.failed &&
         !keys.failed && !img.failed;
    free(offsets.p);
    free(counts.p);
    free(matrix.p);
    free(keys.p);
    free(img.p);
    if (!ok) {
        free(file.p);
        return 0;
    }
    *out = file.p;
    *out_size = file.size;
    return 1;
}

/* Writes the first `keep` bytes of the TIFF (all of it when keep is (size_t)-1). */
static int tiff_write(const char* path, const tiff_spec* sp, size_t keep)
{
    unsigned char* p;
    size_t size;
    int ok;
    if (!tiff_build(sp, &p, &size))
        return 0;
    ok = write_bytes(path, p, keep < size ? keep : size);
    free(p);
    return ok;
}

static int write_vrt(const char* path, int w, int h, const char* srs, const char* gt)
{
    char xml[1024];
    snprintf(xml, sizeof xml,
             "<VRTDataset rasterXSize=\"%d\" rasterYSize=\"%d\">\n"
             "%s%s%s"
             "  <GeoTransform>%s</GeoTransform>\n"
             "  <VRTRasterBand dataType=\"Float32\" band=\"1\"/>\n"
             "</VRTDataset>\n",
             w, h, srs ? "  <SRS>" : "", srs ? srs : "", srs ? "</SRS>\n" : "", gt);
    return write_text(path, xml);
}

static int write_random(const char* path, size_t size, uint64_t seed)
{
    unsigned char* p = (unsigned char*)malloc(size);
    tp_rng r = tp_rng_seed(seed);
    size_t i;
    int ok;
    if (!p)
        return 0;
    for (i = 0; i < size; ++i)
        p[i] = (unsigned char)(tp_rng_u64(&r) >> 56);
    ok = write_bytes(path, p, size);
    free(p);
    return ok;
}

/* ---------------------------------------------------------------------------------------------
 * The bad files, one per case: name (also the CLI test's), file name, writer, expected status
 * and a piece of the expected message.
 */
static const double gt_utm[6] = {500000, 30, 0, 4600000, 0, -30};

static int make_nothing(const char* path)
{
    (void)path;
    return 1;
}
static int make_directory(const char* path)
{
    return mkdir(path, 0700) == 0;
}
static int make_empty(const char* path)
{
    return write_bytes(path, "", 0);
}

/* A whole 16x16 Int16 GeoTIFF (used cut short by the tests). */
static const tiff_spec small_int16 = {16, 16, 0, NULL, 4, 0, gt_utm, 0, NULL};
static int make_truncated_geotiff(const char* path)
{
    return tiff_write(path, &small_int16, 100); /* inside the IFD */
}
static int make_random_tif(const char* path)
{
    return write_random(path, 4096, 1);
}
static int make_random_hgt(const char* path)
{
    return write_random(path, 4096, 2);
}
static int make_hgt_wrong_size(const char* path)
{
    return write_random(path, 1201 * 1200 * 2, 3); /* one row short */
}
static int make_rotated(const char* path)
{
    return write_vrt(path, 8, 8, NULL, "500000, 30, 2.5, 4600000, 1.5, -30");
}
static int make_zero_cellsize(const char* path)
{
    return write_text(path, "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize 0\n"
                            "1 2 3\n4 5 6\n");
}
static int make_negative_cellsize(const char* path)
{
    return write_text(path, "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize -10\n"
                            "1 2 3\n4 5 6\n");
}
static int make_non_finite_geotransform(const char* path)
{
    return write_vrt(path, 8, 8, NULL, "nan, 30, 0, 4600000, 0, -30");
}
/* 10^6 x 10^6 Float32 = 4e12 bytes = 3725.3 GiB: more than any machine these tests run on. */
static int make_huge(const char* path)
{
    return write_vrt(path, 1000000, 1000000, NULL, "500000, 1, 0, 4600000, 0, -1");
}
static int make_all_nodata(const char* path)
{
    int16_t v[6 * 4];
    const tiff_spec sp = {6, 4, 0, v, 0, 0, gt_utm, 0, "-9999"};
    int i;
    for (i = 0; i < 6 * 4; ++i)
        v[i] = -9999;
    return tiff_write(path, &sp, (size_t)-1);
}
static int make_filled_float(const char* path, float value)
{
    float v[6 * 4];
    const tiff_spec sp = {6, 4, 1, v, 0, 0, gt_utm, 0, NULL};
    int i;
    for (i = 0; i < 6 * 4; ++i)
        v[i] = value;
    return tiff_write(path, &sp, (size_t)-1);
}
static int make_all_nan(const char* path)
{
    return make_filled_float(path, NAN);
}
static int make_all_inf(const char* path)
{
    return make_filled_float(path, INFINITY);
}
/* 8 x 8 posts of 0.5 degrees from 95N: the rows run from 94.75N to 91.25N. */
static int make_north_of_pole(const char* path)
{
    static const double gt[6] = {10, 0.5, 0, 95, 0, -0.5};
    const tiff_spec sp = {8, 8, 0, NULL, 0, 0, gt, 1, NULL};
    return tiff_write(path, &sp, (size_t)-1);
}
/* 64 x 64 Int16 in strips of 8 rows, cut in the middle of the fifth strip. */
static const tiff_spec striped = {64, 64, 0, NULL, 8, 0, gt_utm, 0, NULL};
static size_t striped_size(void)
{
    unsigned char* p;
    size_t size = 0;
    if (tiff_build(&striped, &p, &size))
        free(p);
    return size;
}
static int make_cut_strips(const char* path)
{
    size_t size = striped_size();
    return size && tiff_write(path, &striped, size - 64 * 8 * 2 * 3 - 100);
}

/* ---------------------------------------------------------------------------------------------
 * PNG files: signature, IHDR, IDAT, IEND with real CRCs (libpng checks them), the image data a
 * zlib stream of stored (uncompressed) deflate blocks, so no zlib is needed here.
 */
static uint32_t crc32_of(uint32_t crc, const unsigned char* p, size_t n)
{
    size_t i;
    int k;
    crc = ~crc;
    for (i = 0; i < n; ++i) {
        crc ^= p[i];
        for (k = 0; k < 8; ++k)
            crc = crc & 1 ? 0xedb88320u ^ (crc >> 1) : crc >> 1;
    }
    return ~crc;
}
static void put_be32(bytes* b, uint32_t v)
{
    unsigned char c[4] = {(unsigned char)(v >> 24), (unsigned char)(v >> 16 & 0xff),
                          (unsigned char)(v >> 8 & 0xff), (unsigned char)(v & 0xff)};
    put(b, c, 4);
}
static void png_chunk(bytes* b, const char* type, const unsigned char* data, size_t n)
{
    uint32_t crc = crc32_of(0, (const unsigned char*)type, 4);
    crc = crc32_of(crc, data, n);
    put_be32(b, (uint32_t)n);
    put(b, type, 4);
    if (n)
        put(b, data, n);
    put_be32(b, crc);
}
/* A PNG of w x h 16-bit grey pixels: IDAT holds `idat` (NULL: the real rows, sample x + y). */
static int png_build(uint32_t w, uint32_t h, const unsigned char* idat, size_t idat_size,
                     bytes* out)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char ihdr[13] = {0, 0, 0, 0, 0, 0, 0, 0, 16, 0, 0, 0, 0};
    bytes z = {0}, rows = {0};
    uint32_t x, y, a = 1, b2 = 0;
    size_t i;
    memset(out, 0, sizeof *out);
    for (i = 0; i < 4; ++i) {
        ihdr[i] = (unsigned char)(w >> (24 - 8 * i));
        ihdr[4 + i] = (unsigned char)(h >> (24 - 8 * i));
    }
    put(out, sig, 8);
    png_chunk(out, "IHDR", ihdr, 13);
    if (!idat) {
        for (y = 0; y < h; ++y) {
            unsigned char f = 0;
            put(&rows, &f, 1); /* filter: none */
            for (x = 0; x < w; ++x) {
                unsigned char v[2] = {(unsigned char)((x + y) >> 8), (unsigned char)(x + y)};
                put(&rows, v, 2);
            }
        }
        put(&z, "\x78\x01", 2);
        for (i = 0; i < rows.size; i += 65535) { /* stored blocks */
            size_t n = rows.size - i < 65535 ? rows.size - i : 65535;
            unsigned char hd[5] = {(unsigned char)(i + n == rows.size), (unsigned char)(n & 0xff),
                                   (unsigned char)(n >> 8), (unsigned char)(~n & 0xff),
                                   (unsigned char)(~n >> 8 & 0xff)};
            put(&z, hd, 5);
            put(&z, rows.p + i, n);
        }
        for (i = 0; i < rows.size; ++i) {
            a = (a + rows.p[i]) % 65521;
            b2 = (b2 + a) % 65521;
        }
        put_be32(&z, b2 << 16 | a);
        idat = z.p;
        idat_size = z.size;
    }
    png_chunk(out, "IDAT", idat, idat_size);
    png_chunk(out, "IEND", NULL, 0);
    free(z.p);
    free(rows.p);
    return !out->failed && !z.failed && !rows.failed;
}
static int png_write(const char* path, uint32_t w, uint32_t h, const unsigned char* idat,
                     size_t idat_size, size_t keep)
{
    bytes b;
    int ok = png_build(w, h, idat, idat_size, &b) &&
             write_bytes(path, b.p, keep < b.size ? keep : b.size);
    free(b.p);
    return ok;
}

static int make_fifo(const char* path)
{
    unlink(path); /* from an earlier run */
    return mkfifo(path, 0600) == 0;
}
/* The file: 4 KiB whose IHDR claims 60000 x 60000 16-bit grey (7.2 GB of pixels). */
static int make_png_huge_header(const char* path)
{
    unsigned char idat[4000];
    tp_rng r = tp_rng_seed(4);
    size_t i;
    for (i = 0; i < sizeof idat; ++i)
        idat[i] = (unsigned char)(tp_rng_u64(&r) >> 56);
    return png_write(path, 60000, 60000, idat, sizeof idat, (size_t)-1);
}
static int make_png_truncated(const char* path)
{
    return png_write(path, 64, 64, NULL, 0, 33 + 8 + 4000); /* inside IDAT */
}
static int make_png_bad_crc(const char* path)
{
    bytes b;
    int ok = png_build(16, 16, NULL, 0, &b);
    if (ok) {
        b.p[8 + 8 + 5] ^= 0x40; /* a bit of the IHDR's height: its CRC no longer matches */
        ok = write_bytes(path, b.p, b.size);
    }
    free(b.p);
    return ok;
}
/* Chunks and CRCs whole, the deflate stream inside IDAT garbage: only the decoder (libpng) can
 * find it, and libpng prints "libpng error: ..." itself. */
static int make_png_corrupt_idat(const char* path)
{
    unsigned char idat[600];
    tp_rng r = tp_rng_seed(5);
    size_t i;
    for (i = 0; i < sizeof idat; ++i)
        idat[i] = (unsigned char)(tp_rng_u64(&r) >> 56);
    idat[0] = 0x78; /* a valid zlib header, then garbage */
    idat[1] = 0x01;
    return png_write(path, 16, 16, idat, sizeof idat, (size_t)-1);
}
/* A binary PGM header claiming 10^6 x 10^6 16-bit samples: 8e12 bytes to decode and keep. */
static int make_pgm_huge(const char* path)
{
    return write_text(path, "P5\n1000000 1000000\n65535\n0123456789abcdef");
}
static int make_asc_bad_token(const char* path)
{
    return write_text(path, "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize 10\n"
                            "1 2 3\n4 307x 6\n");
}
static int make_asc_extra_rows(const char* path)
{
    return write_text(path, "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize 10\n"
                            "1 2 3\n4 5 6\n7 8 9\n10 11 12\n");
}
static int make_tiny_pixel(const char* path)
{
    return write_vrt(path, 8, 8, NULL, "500000, 1e-300, 0, 4600000, 0, -1e-300");
}
static int make_huge_pixel(const char* path)
{
    return write_vrt(path, 8, 8, NULL, "0, 1e300, 0, 0, 0, -1e300");
}
static int make_far_origin(const char* path)
{
    return write_vrt(path, 8, 8, "EPSG:32631", "1e12, 30, 0, 4600000, 0, -30");
}
/* data/N42E001.dt1 with one bit of column 100 flipped (see the DTED test); writes
 * nothing when the data is missing (the CLI test is registered only when it is there). */
static char* read_whole(const char* path, size_t* size);
static int make_dted_bad_checksum(const char* path)
{
    char src[1024];
    size_t size = 0;
    char* p;
    int ok;
    if (!tp_test_data_path(src, sizeof src, "TP_SHARED_DATA_DIR", "N42E001.dt1"))
        return 1;
    p = read_whole(src, &size);
    if (!p || size != 2902642) {
        free(p);
        return 0;
    }
    p[3428 + 100 * 2414 + 8 + 600 * 2] ^= 0x40; /* +16384 m */
    ok = write_bytes(path, p, size);
    free(p);
    return ok;
}
static int make_geographic_huge_pixel(const char* path)
{
    return write_vrt(path, 4, 3, "EPSG:4326", "10, 20, 0, 50, 0, -20");
}

/* A fuzzer's finding (tests/fuzz/regressions/fuzz_dem_read): a 16x16 GeoTIFF of 21072
 * pixel-interleaved UInt16 bands in one strip of 12048 rows, which GDAL would decode whole
 * (8 GB) to give band 1's 256 samples. */
static const unsigned char huge_block_tif[] = {
    0x49, 0x49, 0x2a, 0x00, 0x08, 0x00, 0x00, 0x00, 0x13, 0x00, 0x00, 0x01, 0x03, 0x00, 0x01, 0x00,
    0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x01, 0x01, 0x03, 0x00, 0x01, 0x00, 0x00, 0x00, 0x10, 0x00,
    0x00, 0x00, 0x02, 0x01, 0x03, 0x00, 0x01, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x03, 0x01,
    0x03, 0x00, 0x01, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00, 0x06, 0x01, 0x03, 0x00, 0x01, 0x00,
    0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x15, 0x01, 0x03, 0x00, 0x01, 0x00, 0x00, 0x00, 0x50, 0x52,
    0x4a, 0x20, 0x4e, 0x61, 0x6d, 0x65, 0x20, 0x3d, 0x20, 0x00, 0x01, 0x00, 0x00, 0x00, 0x3d, 0x01,
    0x03, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x42, 0x01, 0x03, 0x00, 0x01, 0x00,
    0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x43, 0x01, 0x03, 0x00, 0x01, 0x00, 0x00, 0x00, 0x10, 0x2f,
    0x00, 0x00, 0x44, 0x01, 0x04, 0x00, 0x01, 0x00, 0x00, 0x00, 0xfa, 0x01, 0x00, 0x00, 0x45, 0x01,
    0x04, 0x00, 0x01, 0x00, 0x00, 0x00, 0xe8, 0x20, 0x55, 0x54, 0x4d, 0x20, 0x7a, 0x6f, 0x6e, 0x65,
    0x20, 0x31, 0x33, 0x4e, 0x7c, 0x4e, 0x41, 0x44, 0x38, 0x33, 0x7c, 0x00, 0x78, 0x9c, 0x4d, 0x8f,
    0xd7, 0x6e, 0xc2, 0x40, 0x14, 0x05, 0x49, 0x08, 0x22, 0x1e, 0xc7, 0x1d, 0xeb, 0x74, 0x62, 0xb3,
    0x55, 0xb6, 0xe3, 0x5b, 0x3d, 0x2d, 0x0d, 0x47, 0x25, 0x8f, 0x49, 0xc9, 0xed, 0x06, 0x63, 0x7b,
    0x95, 0xd9, 0xe2, 0xbc, 0xb6, 0x9b, 0xf9, 0x86, 0x4e, 0x66, 0x60, 0x60, 0x64, 0xa0, 0x07, 0x02,
    0x12, 0x4d, 0xd6, 0xb2, 0x67, 0xd9, 0x51, 0x4c, 0x8c, 0xf2, 0x29, 0x95, 0x4d, 0x40, 0x5b, 0x3b,
    0x31, 0x31, 0x73, 0x61, 0xb6, 0xbe, 0xb4, 0xb3, 0xeb, 0xd4, 0xcc, 0xc2, 0xc2, 0x85, 0x1b, 0x57,
    0x5c, 0x22, 0x32, 0xe5, 0x36, 0x77, 0x67, 0xb1, 0x70, 0xe5, 0xc6, 0x0f, 0x77, 0xee, 0x3c, 0x01,
    0xa4, 0xf2, 0x27, 0xa4,
};
static int make_huge_block(const char* path)
{
    return write_bytes(path, huge_block_tif, sizeof huge_block_tif);
}

typedef struct bad_case {
    const char* name;
    const char* file;
    int (*make)(const char* path);
    tp_status status;
    const char* needle; /* the message contains it (besides the file name) */
} bad_case;

static const bad_case bad_cases[] = {
    {"missing_file", "no_such_dem.tif", make_nothing, TP_ERR_IO, "No such file"},
    {"directory", "a_directory.tif", make_directory, TP_ERR_IO, "Is a directory"},
    {"empty_file", "empty.tif", make_empty, TP_ERR_BAD_DATA, "empty file"},
    {"truncated_geotiff", "truncated.tif", make_truncated_geotiff, TP_ERR_BAD_DATA, ""},
    {"random_tif", "random.tif", make_random_tif, TP_ERR_BAD_DATA, "not a raster GDAL can open"},
    {"random_hgt", "N42E001.hgt", make_random_hgt, TP_ERR_BAD_DATA, "has 4096 bytes"},
    {"hgt_wrong_size", "N43E001.hgt", make_hgt_wrong_size, TP_ERR_BAD_DATA, "has 2882400 bytes"},
    {"rotated", "rotated.vrt", make_rotated, TP_ERR_BAD_DATA,
     "rotated geotransform (gt[2]=2.5, gt[4]=1.5) is not supported"},
    {"zero_cellsize", "zero_cellsize.asc", make_zero_cellsize, TP_ERR_BAD_DATA,
     "pixel size must be non-zero"},
    {"negative_cellsize", "negative_cellsize.asc", make_negative_cellsize, TP_ERR_BAD_DATA,
     "pixel width must be positive"},
    {"non_finite_geotransform", "nan_origin.vrt", make_non_finite_geotransform, TP_ERR_BAD_DATA,
     "geotransform is not finite"},
    {"huge", "huge.vrt", make_huge, TP_ERR_OUT_OF_MEMORY, "would need 3725.3 GiB"},
    {"all_nodata", "all_nodata.tif", make_all_nodata, TP_ERR_BAD_DATA,
     "all 24 samples are nodata (24 equal to the nodata tag)"},
    {"all_nan", "all_nan.tif", make_all_nan, TP_ERR_BAD_DATA, "all 24 samples are nodata (24 NaN)"},
    {"all_inf", "all_inf.tif", make_all_inf, TP_ERR_BAD_DATA, "24 infinite"},
    {"north_of_pole", "north_of_pole.tif", make_north_of_pole, TP_ERR_BAD_DATA,
     "rows reach latitude 94.75"},
    {"cut_strips", "cut_strips.tif", make_cut_strips, TP_ERR_BAD_DATA,
     "reading the heights of band 1 failed"},
    {"fifo", "fifo.tif", make_fifo, TP_ERR_IO, "it is a FIFO (named pipe), not a regular file"},
    {"fifo_png", "fifo.png", make_fifo, TP_ERR_IO, "it is a FIFO (named pipe), not a regular file"},
    {"directory_png", "a_directory.png", make_directory, TP_ERR_IO,
     "Is a directory, expected an image file"},
    {"png_huge_header", "huge_header.png", make_png_huge_header, TP_ERR_BAD_DATA,
     "PNG header claims 60000x60000 16-bit grey pixels (7.2 GB), but its 4000 bytes"},
    {"png_truncated", "truncated.png", make_png_truncated, TP_ERR_BAD_DATA,
     "PNG is truncated: chunk IDAT at byte 33"},
    {"png_bad_crc", "bad_crc.png", make_png_bad_crc, TP_ERR_BAD_DATA,
     "PNG chunk IHDR at byte 8 is corrupt: CRC"},
    {"png_corrupt_idat", "corrupt_idat.png", make_png_corrupt_idat, TP_ERR_BAD_DATA,
     "cannot read the pixels"},
    {"pgm_huge", "huge.pgm", make_pgm_huge, TP_ERR_OUT_OF_MEMORY,
     "1000000x1000000 samples would need 7450.6 GiB"},
    {"asc_bad_token", "bad_token.asc", make_asc_bad_token, TP_ERR_BAD_DATA,
     "line 7: '307x' is not a number"},
    {"asc_extra_rows", "extra_rows.asc", make_asc_extra_rows, TP_ERR_BAD_DATA,
     "12 values where the header's nrows 2 x ncols 3 asks for 6 (2 extra rows): the extra values "
     "start on line 8"},
    {"tiny_pixel", "tiny_pixel.vrt", make_tiny_pixel, TP_ERR_BAD_DATA,
     "pixel width 1e-300 (gt[1]) is outside 1e-08 .. 1e+06"},
    {"huge_pixel", "huge_pixel.vrt", make_huge_pixel, TP_ERR_BAD_DATA,
     "pixel width 1e+300 (gt[1]) is outside 1e-08 .. 1e+06"},
    {"far_origin", "far_origin.vrt", make_far_origin, TP_ERR_BAD_DATA,
     "west edge at x = 1e+12 m is outside -1e+08 .. 1e+08 m"},
    {"dted_bad_checksum", "N42E001.dt1", make_dted_bad_checksum, TP_ERR_BAD_DATA,
     "DTED checksum mismatch, the elevations are corrupt (at column 100"},
    {"geographic_huge_pixel", "geographic_huge_pixel.vrt", make_geographic_huge_pixel,
     TP_ERR_BAD_DATA, "pixel width 20 degrees (gt[1]) is outside 1e-08 .. 10 degrees"},
    {"huge_block", "huge_block.tif", make_huge_block, TP_ERR_BAD_DATA,
     "one block of this 16x16 raster is 16x12048 samples of 21072 interleaved bands"},
};
#define BAD_CASE_COUNT (sizeof bad_cases / sizeof bad_cases[0])

#ifndef TP_TEST_NO_IO
static const bad_case* find_case(const char* name)
{
    size_t i;
    for (i = 0; i < BAD_CASE_COUNT; ++i)
        if (strcmp(bad_cases[i].name, name) == 0)
            return &bad_cases[i];
    return NULL;
}

/* ---------------------------------------------------------------------------------------------
 * A temporary directory per test: made by tmp_begin, removed (with its files) by tmp_end, or by
 * the next tmp_begin or at exit when a failed assertion jumped over tmp_end.
 */
static char tmp_dir[256];

static void remove_tree(const char* dir)
{
    DIR* d = opendir(dir);
    struct dirent* ent;
    char path[512];
    if (d) {
        while ((ent = readdir(d)) != NULL) {
            if (!strcmp(ent->d_name, ".") || !strcmp(ent->d_name, ".."))
                continue;
            snprintf(path, sizeof path, "%s/%s", dir, ent->d_name);
            if (unlink(path) != 0)
                remove_tree(path); /* a directory of a test case */
        }
        closedir(d);
    }
    rmdir(dir);
}

static void tmp_end(void)
{
    if (tmp_dir[0])
        remove_tree(tmp_dir);
    tmp_dir[0] = '\0';
}

static void tmp_begin(void)
{
    static int registered;
    const char* base = getenv("TMPDIR");
    if (!registered) {
        atexit(tmp_end);
        registered = 1;
    }
    tmp_end();
    if (!base || !*base)
        base = "/tmp";
    snprintf(tmp_dir, sizeof tmp_dir, "%s/tp_bad_input_XXXXXX", base);
    if (!mkdtemp(tmp_dir)) {
        tmp_dir[0] = '\0';
        FAIL("mkdtemp in %s: %s", base, strerror(errno));
    }
}

static void tmp_path(char* buf, size_t cap, const char* file)
{
    ASSERT_TRUE((size_t)snprintf(buf, cap, "%s/%s", tmp_dir, file) < cap);
}

/* ---------------------------------------------------------------------------------------------
 * Checks
 */
#define REQUIRE_IO() ((void)0)

/* As `terrapatch` reads a DEM (app/scene/scene.c): heightmap images through OpenImageIO. */
static tp_status read_any(const char* path, tp_dem** out, tp_error* err)
{
    return tp_is_heightmap_image(path) ? tp_dem_read_image(path, NULL, out, err)
                                       : tp_dem_read(path, out, err);
}

/* tp_dem_read(path) must give `status`, a message naming `name` and containing `needle`, and
 * leave the out-parameter alone; also with a NULL tp_error. Returns the message. */
static const char* expect_refused(const char* path, const char* name, tp_status status,
                                  const char* needle)
{
    static tp_error err;
    tp_dem* sentinel = (tp_dem*)&sentinel;
    tp_dem* out = sentinel;
    tp_status s;
    memset(&err, 0, sizeof err);
    s = read_any(path, &out, &err);
    if (s == TP_OK && out != sentinel)
        tp_dem_destroy(out);
    EXPECT_STATUS(status, s);
    EXPECT_TRUE(out == sentinel);
    EXPECT_CONTAINS(err.message, name);
    if (needle && *needle)
        EXPECT_CONTAINS(err.message, needle);
    EXPECT_TRUE(strchr(err.message, '\n') == NULL);
    out = sentinel;
    s = read_any(path, &out, NULL);
    if (s == TP_OK && out != sentinel)
        tp_dem_destroy(out);
    EXPECT_STATUS(status, s);
    EXPECT_TRUE(out == sentinel);
    return err.message;
}

/* Writes the case's file into a fresh temporary directory and checks that it is refused. */
static void check_case(const char* name)
{
    const bad_case* c = find_case(name);
    char path[512];
    const char* msg;
    ASSERT_TRUE(c != NULL);
    tmp_begin();
    tmp_path(path, sizeof path, c->file);
    ASSERT_TRUE(c->make(path));
    msg = expect_refused(path, c->file, c->status, c->needle);
    tp_test_note("%s", msg);
    tmp_end();
}

/* Reads a file that must be accepted; the caller destroys the result. */
static tp_dem* expect_read(const char* path)
{
    tp_dem* dem = NULL;
    tp_error err;
    tp_status s;
    memset(&err, 0, sizeof err);
    s = tp_dem_read(path, &dem, &err);
    if (s != TP_OK)
        FAIL("tp_dem_read(%s): %s: %s", path, tp_test_status_name_(s), err.message);
    ASSERT_TRUE(dem != NULL);
    return dem;
}
#else
#define REQUIRE_IO() SKIP("built without tp_io")
#endif

/* ---------------------------------------------------------------------------------------------
 * Tests
 */
TEST(missing_file_is_io_error)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("missing_file");
#endif
}

TEST(directory_is_io_error)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("directory");
#endif
}

TEST(empty_file_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("empty_file");
#endif
}

/* Cut at every 5th byte up to the image (header, IFD, transform, offsets and counts), then at
 * a few points in the image: every cut is refused, whether when opening or when reading. */
TEST(truncated_geotiff_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        unsigned char* p;
        size_t size, keep, tries = 0;
        char path[512];
        check_case("truncated_geotiff");
        ASSERT_TRUE(tiff_build(&small_int16, &p, &size));
        free(p);
        tmp_begin();
        tmp_path(path, sizeof path, "cut.tif");
        for (keep = 1; keep < size; keep += keep < size - 16 * 16 * 2 ? 5 : 97) {
            tp_dem* sentinel = (tp_dem*)&sentinel;
            tp_dem* out = sentinel;
            tp_error err;
            tp_status s;
            ASSERT_TRUE(tiff_write(path, &small_int16, keep));
            memset(&err, 0, sizeof err);
            s = tp_dem_read(path, &out, &err);
            ++tries;
            if (s == TP_OK || out != sentinel || !strstr(err.message, "cut.tif")) {
                if (out != sentinel)
                    tp_dem_destroy(out);
                FAIL("cut at %zu of %zu bytes: %s, \"%s\"", keep, size, tp_test_status_name_(s),
                     err.message);
            }
        }
        /* and the whole file reads */
        ASSERT_TRUE(tiff_write(path, &small_int16, (size_t)-1));
        tp_dem_destroy(expect_read(path));
        tp_test_note("%zu cut points of a %zu-byte GeoTIFF refused", tries, size);
        tmp_end();
    }
#endif
}

TEST(random_bytes_named_tif_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("random_tif");
#endif
}

TEST(random_bytes_named_hgt_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("random_hgt");
#endif
}

/* 1201 x 1200 samples: one row short of SRTM3; the message gives the sizes that would do. */
TEST(hgt_of_wrong_size_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("hgt_wrong_size");
    {
        const char* msg;
        char path[512];
        tmp_begin();
        tmp_path(path, sizeof path, "N43E001.hgt");
        ASSERT_TRUE(make_hgt_wrong_size(path));
        msg = expect_refused(path, "N43E001.hgt", TP_ERR_BAD_DATA, "1201x1201 (2884802 bytes)");
        EXPECT_CONTAINS(msg, "3601x3601 (25934402 bytes)");
        tmp_end();
    }
#endif
}

/* A VRT and a GeoTIFF whose ModelTransformation has shear terms. */
TEST(rotated_geotransform_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("rotated");
    {
        static const double gt[6] = {500000, 30, 0, 4600000, -4, -30};
        const tiff_spec sp = {8, 8, 0, NULL, 0, 0, gt, 0, NULL};
        char path[512];
        tmp_begin();
        tmp_path(path, sizeof path, "rotated.tif");
        ASSERT_TRUE(tiff_write(path, &sp, (size_t)-1));
        expect_refused(path, "rotated.tif", TP_ERR_BAD_DATA, "gt[2]=0, gt[4]=-4");
        tmp_end();
    }
#endif
}

/* ESRI ASCII "cellsize 0", and a VRT with a zero pixel height. */
TEST(zero_pixel_size_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("zero_cellsize");
    {
        char path[512];
        tmp_begin();
        tmp_path(path, sizeof path, "zero_height.vrt");
        ASSERT_TRUE(write_vrt(path, 8, 8, NULL, "500000, 30, 0, 4600000, 0, 0"));
        expect_refused(path, "zero_height.vrt", TP_ERR_BAD_DATA,
                       "pixel size must be non-zero, got 30 x 0");
        tmp_end();
    }
#endif
}

/* ESRI ASCII "cellsize -10" (GDAL makes it gt[1] = -10, gt[5] = +10), and a VRT whose columns
 * run west: both refused. */
TEST(negative_pixel_width_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("negative_cellsize");
    {
        char path[512];
        tmp_begin();
        tmp_path(path, sizeof path, "west.vrt");
        ASSERT_TRUE(write_vrt(path, 8, 8, NULL, "500000, -30, 0, 4600000, 0, -30"));
        expect_refused(path, "west.vrt", TP_ERR_BAD_DATA, "got gt[1]=-30");
        tmp_end();
    }
#endif
}

/* Bottom-up rows (gt[5] > 0, as XYZ and some NetCDF grids have) are a valid layout the core
 * handles: read as they are, not refused and not flipped. */
TEST(bottom_up_rows_are_read_as_they_are)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        static const double gt[6] = {500000, 30, 0, 4600000, 0, 30};
        static const float v[4 * 3] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
        const tiff_spec sp = {4, 3, 1, v, 0, 0, gt, 0, NULL};
        char path[512];
        tp_dem* dem;
        int i;
        tmp_begin();
        tmp_path(path, sizeof path, "bottom_up.tif");
        ASSERT_TRUE(tiff_write(path, &sp, (size_t)-1));
        dem = expect_read(path);
        for (i = 0; i < 6; ++i)
            EXPECT_EQ_DBL(gt[i], dem->geotransform[i]);
        for (i = 0; i < 12; ++i)
            EXPECT_EQ_DBL(v[i], dem->heights[i]);
        tp_dem_destroy(dem);
        tmp_end();
    }
#endif
}

TEST(non_finite_geotransform_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("non_finite_geotransform");
#endif
}

/* A 10^6 x 10^6 VRT (a 300-byte file) and an ESRI ASCII grid whose header claims the same: the
 * size is refused before any allocation (under AddressSanitizer a 4 TB malloc would abort). */
TEST(raster_larger_than_memory_is_refused_before_allocating)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("huge");
    {
        char path[512];
        const char* msg;
        tmp_begin();
        tmp_path(path, sizeof path, "huge.asc");
        ASSERT_TRUE(write_text(path, "ncols 1000000\nnrows 1000000\nxllcorner 0\nyllcorner 0\n"
                                     "cellsize 1\n1 2 3\n"));
        msg = expect_refused(path, "huge.asc", TP_ERR_OUT_OF_MEMORY,
                             "1000000x1000000 samples would need 3725.3 GiB");
        EXPECT_CONTAINS(msg, "GiB of memory this machine has");
        tmp_end();
    }
#endif
}

TEST(all_nodata_raster_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("all_nodata");
#endif
}

TEST(all_nan_raster_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("all_nan");
#endif
}

TEST(all_infinite_raster_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("all_inf");
#endif
}

/* +-Inf (and +-FLT_MAX, which is what GDAL stores for "inf" in a text grid) among valid heights
 * are nodata: counted as voids, left out of min/max, with a warning. Not an error. */
TEST(infinite_heights_are_nodata_with_warning)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const float v[4 * 2] = {10, INFINITY, 30, -INFINITY, 50, FLT_MAX, -FLT_MAX, 80.5f};
        const tiff_spec sp = {4, 2, 1, v, 0, 0, gt_utm, 0, NULL};
        char path[512];
        tp_dem* dem;
        tmp_begin();
        tmp_path(path, sizeof path, "some_inf.tif");
        ASSERT_TRUE(tiff_write(path, &sp, (size_t)-1));
        dem = expect_read(path);
        EXPECT_EQ_INT(4, dem->void_count);
        EXPECT_EQ_DBL(10.0, dem->min_m);
        EXPECT_EQ_DBL(80.5, dem->max_m);
        EXPECT_NAN(dem->heights[1]);
        EXPECT_NAN(dem->heights[3]);
        EXPECT_NAN(dem->heights[5]);
        EXPECT_NAN(dem->heights[6]);
        EXPECT_EQ_DBL(30.0, dem->heights[2]);
        EXPECT_CONTAINS(dem->warnings, "4 infinite samples");
        EXPECT_CONTAINS(dem->warnings, "some_inf.tif");
        tp_dem_destroy(dem);
        tmp_end();
    }
#endif
}

/* EPSG:4326 rows from 94.75N (and, mirrored, to 94.75S): refused. */
TEST(latitude_beyond_90_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("north_of_pole");
    {
        static const double gt[6] = {10, 0.5, 0, -87, 0, -0.5};
        const tiff_spec sp = {8, 8, 0, NULL, 0, 0, gt, 1, NULL};
        char path[512];
        const char* msg;
        tmp_begin();
        tmp_path(path, sizeof path, "south_of_pole.tif");
        ASSERT_TRUE(tiff_write(path, &sp, (size_t)-1));
        msg = expect_refused(path, "south_of_pole.tif", TP_ERR_BAD_DATA,
                             "rows reach latitude -90.75");
        EXPECT_CONTAINS(msg, "beyond -90");
        tmp_end();
    }
#endif
}

/* A grid-registered global grid: posts on both poles, so its outer edges are half a pixel
 * beyond them. Sample centres are what must lie within +-90; this one is read. The same
 * numbers in a projected CRS are not latitudes and are not checked. */
TEST(global_grid_with_posts_on_the_poles_is_read)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        static const double gt[6] = {-181, 2, 0, 91, 0, -2}; /* 181 x 91 posts every 2 degrees */
        static const double beyond[6] = {0, 1, 0, 120, 0, -1};
        const tiff_spec sp = {181, 91, 0, NULL, 0, 0, gt, 1, NULL};
        const tiff_spec projected = {8, 8, 0, NULL, 0, 0, beyond, 0, NULL};
        char path[512];
        tp_dem* dem;
        tmp_begin();
        tmp_path(path, sizeof path, "global.tif");
        ASSERT_TRUE(tiff_write(path, &sp, (size_t)-1));
        dem = expect_read(path);
        EXPECT_EQ_INT(4326, dem->epsg);
        EXPECT_EQ_INT(91, dem->height);
        tp_dem_destroy(dem);
        tmp_path(path, sizeof path, "no_crs.tif");
        ASSERT_TRUE(tiff_write(path, &projected, (size_t)-1));
        tp_dem_destroy(expect_read(path));
        tmp_end();
    }
#endif
}

/* The IFD is whole, so the file opens; a strip is cut short, so GDAL fails in RasterIO. That
 * failure is the result, with no partial raster; the same for a tiled layout. */
TEST(truncated_strip_data_fails_while_reading)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("cut_strips");
    {
        const tiff_spec tiled = {64, 64, 1, NULL, 0, 32, gt_utm, 0, NULL};
        unsigned char* p;
        size_t size;
        char path[512];
        ASSERT_TRUE(tiff_build(&tiled, &p, &size));
        free(p);
        tmp_begin();
        tmp_path(path, sizeof path, "cut_tiles.tif");
        ASSERT_TRUE(tiff_write(path, &tiled, size - 32 * 32 * 4 / 2)); /* half the last tile */
        expect_refused(path, "cut_tiles.tif", TP_ERR_BAD_DATA,
                       "reading the heights of band 1 failed");
        /* whole, both layouts read */
        ASSERT_TRUE(tiff_write(path, &tiled, (size_t)-1));
        tp_dem_destroy(expect_read(path));
        tmp_path(path, sizeof path, "whole_strips.tif");
        ASSERT_TRUE(tiff_write(path, &striped, (size_t)-1));
        tp_dem_destroy(expect_read(path));
        tmp_end();
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Inputs that are not regular files: opening a FIFO blocks until a writer comes, so these are
 * refused before anything opens them. alarm() turns a regression into a failure, not a hang
 * (and tests/CMakeLists.txt gives the test a short TIMEOUT as well).
 */
TEST(fifo_is_refused_without_blocking)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    alarm(20);
    check_case("fifo");
    check_case("fifo_png");
    alarm(0);
#endif
}

TEST(directory_as_heightmap_is_io_error)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("directory_png");
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Heightmap images: the header is checked before anything of its size is allocated.
 */
TEST(png_header_larger_than_its_data_is_refused_before_decoding)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("png_huge_header");
#endif
}

TEST(truncated_png_is_refused_saying_where)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("png_truncated");
#endif
}

TEST(png_with_bad_crc_is_refused)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("png_bad_crc");
#endif
}

/* The decoder's failure is ours to report: the message carries libpng's text. The same PNG
 * writer's whole files read, sample for sample. */
TEST(png_with_corrupt_image_data_is_refused)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("png_corrupt_idat");
    {
        char path[512];
        tp_dem* dem = NULL;
        tp_error err;
        tmp_begin();
        tmp_path(path, sizeof path, "whole.png");
        ASSERT_TRUE(png_write(path, 300, 200, NULL, 0, (size_t)-1));
        memset(&err, 0, sizeof err);
        if (tp_dem_read_image(path, NULL, &dem, &err) != TP_OK)
            FAIL("tp_dem_read_image(%s): %s", path, err.message);
        EXPECT_EQ_INT(300, dem->width);
        EXPECT_EQ_INT(200, dem->height);
        EXPECT_EQ_DBL(0.0, dem->min_m);
        EXPECT_EQ_DBL(299.0 + 199.0, dem->max_m);
        EXPECT_EQ_DBL(5.0 + 7.0, dem->heights[7 * 300 + 5]);
        tp_dem_destroy(dem);
        tmp_end();
    }
#endif
}

TEST(heightmap_larger_than_memory_is_refused_before_allocating)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    const char* msg;
    char path[512];
    check_case("pgm_huge");
    tmp_begin();
    tmp_path(path, sizeof path, "huge.pgm");
    ASSERT_TRUE(make_pgm_huge(path));
    msg = expect_refused(path, "huge.pgm", TP_ERR_OUT_OF_MEMORY, "GiB of memory this machine has");
    EXPECT_CONTAINS(msg, "for the decoded pixels, a copy of them and the heights");
    tmp_end();
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Damaged copies of real files.
 */
static char* read_whole(const char* path, size_t* size)
{
    FILE* f = fopen(path, "rb");
    char* p = NULL;
    long n;
    if (!f)
        return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (p = (char*)malloc((size_t)n + 1)) != NULL) {
        *size = fread(p, 1, (size_t)n, f);
        p[*size] = '\0';
    }
    fclose(f);
    return p;
}

/* Where line `line` (1-based) starts in text. */
static size_t line_start(const char* text, int line)
{
    size_t at = 0;
    while (--line > 0 && text[at]) {
        while (text[at] && text[at] != '\n')
            ++at;
        if (text[at])
            ++at;
    }
    return at;
}

/* DTED Level 1 (data/N42E001.dt1, 1201 x 1201): header 3428 bytes, then one 2414-byte
 * record per column (8 bytes, 1201 big-endian samples, a 4-byte checksum). One bit of column
 * 100 flipped: refused, naming the column; DTED_VERIFY_CHECKSUM=NO reads it anyway; the
 * undamaged copy reads. */
TEST(dted_with_bad_checksum_is_refused)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char src[1024], path[512];
    size_t size = 0;
    char* p;
    const char* msg;
    tp_dem* dem;
    REQUIRE_DATA_FILE(src, "TP_SHARED_DATA_DIR", "N42E001.dt1");
    p = read_whole(src, &size);
    ASSERT_TRUE(p != NULL && size == 2902642);
    tmp_begin();
    tmp_path(path, sizeof path, "N42E001.dt1");
    ASSERT_TRUE(write_bytes(path, p, size));
    dem = expect_read(path);
    EXPECT_EQ_DBL(3100.0, dem->max_m);
    tp_dem_destroy(dem);
    free(p);
    ASSERT_TRUE(make_dted_bad_checksum(path));
    msg = expect_refused(path, "N42E001.dt1", TP_ERR_BAD_DATA, "DTED checksum mismatch");
    EXPECT_CONTAINS(msg, "at column 100");
    EXPECT_CONTAINS(msg, "DTED_VERIFY_CHECKSUM=NO");
    setenv("DTED_VERIFY_CHECKSUM", "NO", 1);
    dem = expect_read(path);
    unsetenv("DTED_VERIFY_CHECKSUM");
    EXPECT_TRUE(dem->max_m > 16384.0);
    tp_dem_destroy(dem);
    tmp_end();
#endif
}

/* ESRI ASCII grids: GDAL reads "307x" as 307 and ignores rows past nrows. Hand-made grids, then
 * copies of data/front_range_srtmgl3_144.asc (6 header lines, then one line per row). */
TEST(ascii_grid_token_that_is_not_a_number_is_refused)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char src[1024], path[512];
    size_t size = 0, at;
    char* p;
    FILE* f;
    check_case("asc_bad_token");
    REQUIRE_DATA_FILE(src, "TP_SHARED_DATA_DIR", "front_range_srtmgl3_144.asc");
    p = read_whole(src, &size);
    ASSERT_TRUE(p != NULL);
    tmp_begin();
    tmp_path(path, sizeof path, "front_range_bad_token.asc");
    at = line_start(p, 20);
    while (p[at] == ' ')
        ++at;
    while (p[at] >= '0' && p[at] <= '9')
        ++at; /* the end of the first value on line 20 */
    f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    ASSERT_TRUE(fwrite(p, 1, at, f) == at && fputc('x', f) == 'x' &&
                fwrite(p + at, 1, size - at, f) == size - at);
    ASSERT_TRUE(fclose(f) == 0);
    free(p);
    expect_refused(path, "front_range_bad_token.asc", TP_ERR_BAD_DATA, "line 20: '2882x'");
    tmp_end();
#endif
}

TEST(ascii_grid_with_more_or_fewer_values_than_its_header_is_refused)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char src[1024], path[512];
    size_t size = 0, rows_at, extra_end;
    char* p;
    FILE* f;
    tp_dem* dem;
    check_case("asc_extra_rows");
    REQUIRE_DATA_FILE(src, "TP_SHARED_DATA_DIR", "front_range_srtmgl3_144.asc");
    p = read_whole(src, &size);
    ASSERT_TRUE(p != NULL && size > 0 && p[size - 1] == '\n');
    tmp_begin();
    /* 164 rows under "nrows 144": the first 20 rows again at the end */
    tmp_path(path, sizeof path, "front_range_164_rows.asc");
    rows_at = line_start(p, 7);
    extra_end = line_start(p, 27);
    f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    ASSERT_TRUE(fwrite(p, 1, size, f) == size &&
                fwrite(p + rows_at, 1, extra_end - rows_at, f) == extra_end - rows_at);
    ASSERT_TRUE(fclose(f) == 0);
    expect_refused(path, "front_range_164_rows.asc", TP_ERR_BAD_DATA,
                   "23616 values where the header's nrows 144 x ncols 144 asks for 20736 (20 "
                   "extra rows): the extra values start on line 151");
    /* 100 rows of the 144 */
    tmp_path(path, sizeof path, "front_range_100_rows.asc");
    ASSERT_TRUE(write_bytes(path, p, line_start(p, 107)));
    expect_refused(path, "front_range_100_rows.asc", TP_ERR_BAD_DATA,
                   "only 14400 values where the header's nrows 144 x ncols 144 asks for 20736");
    /* the whole file reads, as before */
    tmp_path(path, sizeof path, "front_range.asc");
    ASSERT_TRUE(write_bytes(path, p, size));
    dem = expect_read(path);
    EXPECT_EQ_DBL(2186.0, dem->min_m);
    EXPECT_EQ_DBL(3345.0, dem->max_m);
    tp_dem_destroy(dem);
    free(p);
    tmp_end();
#endif
}

/* The text pass must not refuse what real grids hold and GDAL reads: decimals, signs,
 * exponents, tabs, CRLF, trailing blanks, xllcenter and dx/dy headers, keys in any case or
 * several to a line, a decimal comma and "null" (both read by GDAL's CPLAtofM / nodata), and
 * a DOS end-of-file mark (0x1a) after the last row. */
TEST(ascii_grid_valid_variants_are_read)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const char* const grids[] = {
        "ncols 3\nnrows 3\nxllcorner 500000.5\nyllcorner 4000000\ncellsize 30\n"
        "NODATA_value -9999.0\n1.5 -2.25 1e3\n-9999 -9999.0 4.0E+01\n+7 .5 9.\n",
        "NCOLS\t3\r\nNROWS\t3\r\nXLLCENTER\t500000\r\nYLLCENTER\t4000000\r\nCELLSIZE\t30\r\n"
        "NODATA_VALUE\t-9999\r\n1\t2\t3   \r\n4 5 6 \r\n7 8 9\r\n",
        "ncols 3\nnrows 3\nxllcorner 500000\nyllcorner 4000000\ndx 30\ndy 30\n1 2 3\n4 5 6\n7 8 9",
        "ncols 3 nrows 3\nxllcorner 500000 yllcorner 4000000\ncellsize 30\n1 2 3 4 5 6 7 8 9\n",
        "ncols 3\nnrows 3\nxllcorner 500000\nyllcorner 4000000\ncellsize 30\n"
        "1,5 2,25 3\n4 null 6\n7 8 9\n",
        "ncols 3\r\nnrows 3\r\nxllcorner 0\r\nyllcorner 0\r\ncellsize 1\r\n"
        "1 2 3\r\n4 5 6\r\n7 8 9\r\n\x1a", /* DOS end-of-file mark */
    };
    char path[512], name[32];
    size_t i;
    tp_dem* dem;
    tmp_begin();
    for (i = 0; i < sizeof grids / sizeof grids[0]; ++i) {
        snprintf(name, sizeof name, "valid_%u.asc", (unsigned)i);
        tmp_path(path, sizeof path, name);
        ASSERT_TRUE(write_bytes(path, grids[i], strlen(grids[i])));
        dem = expect_read(path);
        EXPECT_EQ_INT(3, dem->width);
        EXPECT_EQ_INT(3, dem->height);
        tp_dem_destroy(dem);
    }
    /* and what is still damage */
    tmp_path(path, sizeof path, "two_commas.asc");
    {
        const char bad[] = "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                           "1,5,3 2 3\n4 5 6\n7 8 9\n";
        ASSERT_TRUE(write_bytes(path, bad, sizeof bad - 1));
        expect_refused(path, "two_commas.asc", TP_ERR_BAD_DATA, "line 6: '1,5,3' is not a number");
    }
    tmp_path(path, sizeof path, "control_byte.asc");
    {
        const char bad[] = "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                           "1 2 3\n4 5\x01 6\n7 8 9\n";
        ASSERT_TRUE(write_bytes(path, bad, sizeof bad - 1));
        expect_refused(path, "control_byte.asc", TP_ERR_BAD_DATA, "line 7: '5\\x01' is not a number");
    }
    tmp_end();
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Georeferences out of range (tp_io.h's TP_PIXEL_SIZE_* and TP_COORD_MAX_M).
 */
/* A block far larger than the image is refused before GDAL allocates it. */
TEST(a_block_far_larger_than_the_raster_is_refused)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("huge_block");
#endif
}

TEST(absurd_pixel_sizes_and_extents_are_refused)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    check_case("tiny_pixel");
    check_case("huge_pixel");
    check_case("far_origin");
    check_case("geographic_huge_pixel");
    {
        char path[512];
        tmp_begin();
        tmp_path(path, sizeof path, "mm_pixels.vrt"); /* 0.1 mm in UTM */
        ASSERT_TRUE(write_vrt(path, 8, 8, "EPSG:32631", "500000, 1e-4, 0, 4600000, 0, -1e-4"));
        expect_refused(path, "mm_pixels.vrt", TP_ERR_BAD_DATA,
                       "pixel width 0.0001 m (gt[1]) is outside 0.001 .. 1e+06 m");
        tmp_path(path, sizeof path, "east_of_540.vrt");
        ASSERT_TRUE(write_vrt(path, 100, 10, "EPSG:4326", "500, 1, 0, 50, 0, -1"));
        expect_refused(path, "east_of_540.vrt", TP_ERR_BAD_DATA,
                       "east edge at longitude 600 is outside -540 .. 540 degrees");
        tmp_path(path, sizeof path, "span_400.vrt");
        ASSERT_TRUE(write_vrt(path, 100, 10, "EPSG:4326", "-100, 4, 0, 50, 0, -1"));
        expect_refused(path, "span_400.vrt", TP_ERR_BAD_DATA,
                       "spans 400 degrees of longitude (west edge -100, east edge 300)");
        /* longitudes past 360 in a 0 .. 360 grid are places: Britain at 355 .. 365 */
        tmp_path(path, sizeof path, "britain_0_360.vrt");
        ASSERT_TRUE(write_vrt(path, 100, 50, "EPSG:4326", "355, 0.1, 0, 55, 0, -0.1"));
        tp_dem_destroy(expect_read(path));
        /* a global grid with its first column repeated at the end */
        tmp_path(path, sizeof path, "wrap_column.vrt");
        ASSERT_TRUE(write_vrt(path, 145, 60, "EPSG:4326", "-1.25, 2.5, 0, 75, 0, -2.5"));
        tp_dem_destroy(expect_read(path));
        /* the ends of the ranges are read */
        tmp_path(path, sizeof path, "metre_km.vrt");
        ASSERT_TRUE(write_vrt(path, 8, 8, "EPSG:32631", "500000, 0.001, 0, 4600000, 0, -1000"));
        tp_dem_destroy(expect_read(path));
        tmp_end();
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Read, with a warning.
 */
TEST(unreadable_prj_is_warned_about)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[512], prj[512];
    tp_dem* dem;
    tmp_begin();
    tmp_path(path, sizeof path, "grid.asc");
    tmp_path(prj, sizeof prj, "grid.prj");
    ASSERT_TRUE(write_text(path, "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize 10\n"
                                 "1 2 3\n4 5 6\n"));
    dem = expect_read(path);
    EXPECT_TRUE(dem->warnings[0] == '\0');
    tp_dem_destroy(dem);
    ASSERT_TRUE(write_text(prj, "this is { not a CRS\n"));
    dem = expect_read(path);
    EXPECT_TRUE(dem->crs_wkt[0] == '\0');
    EXPECT_CONTAINS(dem->warnings, "grid.asc: ");
    EXPECT_CONTAINS(dem->warnings, "grid.prj could not be read as a CRS");
    tp_dem_destroy(dem);
    tmp_end();
#endif
}

TEST(no_crs_and_no_geotransform_is_warned_about)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[512];
    tp_dem* dem;
    tmp_begin();
    tmp_path(path, sizeof path, "bare.vrt");
    ASSERT_TRUE(write_text(path, "<VRTDataset rasterXSize=\"4\" rasterYSize=\"3\">\n"
                                 "  <VRTRasterBand dataType=\"Float32\" band=\"1\"/>\n"
                                 "</VRTDataset>\n"));
    dem = expect_read(path);
    EXPECT_EQ_INT(0, dem->has_geotransform);
    EXPECT_CONTAINS(dem->warnings, "bare.vrt: no CRS and no geotransform");
    tp_dem_destroy(dem);
    tmp_end();
#endif
}

#define TESTS(X)                                                                                   \
    X(missing_file_is_io_error)                                                                    \
    X(directory_is_io_error)                                                                       \
    X(empty_file_is_bad_data)                                                                      \
    X(truncated_geotiff_is_bad_data)                                                               \
    X(random_bytes_named_tif_is_bad_data)                                                          \
    X(random_bytes_named_hgt_is_bad_data)                                                          \
    X(hgt_of_wrong_size_is_bad_data)                                                               \
    X(rotated_geotransform_is_bad_data)                                                            \
    X(zero_pixel_size_is_bad_data)                                                                 \
    X(negative_pixel_width_is_bad_data)                                                            \
    X(bottom_up_rows_are_read_as_they_are)                                                         \
    X(non_finite_geotransform_is_bad_data)                                                         \
    X(raster_larger_than_memory_is_refused_before_allocating)                                      \
    X(all_nodata_raster_is_bad_data)                                                               \
    X(all_nan_raster_is_bad_data)                                                                  \
    X(all_infinite_raster_is_bad_data)                                                             \
    X(infinite_heights_are_nodata_with_warning)                                                    \
    X(latitude_beyond_90_is_bad_data)                                                              \
    X(global_grid_with_posts_on_the_poles_is_read)                                                 \
    X(truncated_strip_data_fails_while_reading)                                                    \
    X(fifo_is_refused_without_blocking)                                                            \
    X(directory_as_heightmap_is_io_error)                                                          \
    X(png_header_larger_than_its_data_is_refused_before_decoding)                                  \
    X(truncated_png_is_refused_saying_where)                                                       \
    X(png_with_bad_crc_is_refused)                                                                 \
    X(png_with_corrupt_image_data_is_refused)                                                      \
    X(heightmap_larger_than_memory_is_refused_before_allocating)                                   \
    X(dted_with_bad_checksum_is_refused)                                                           \
    X(ascii_grid_token_that_is_not_a_number_is_refused)                                            \
    X(ascii_grid_with_more_or_fewer_values_than_its_header_is_refused)                             \
    X(ascii_grid_valid_variants_are_read)                                                          \
    X(a_block_far_larger_than_the_raster_is_refused)                                               \
    X(absurd_pixel_sizes_and_extents_are_refused)                                                  \
    X(unreadable_prj_is_warned_about)                                                              \
    X(no_crs_and_no_geotransform_is_warned_about)

/* The runner of tp_test.h, plus `--write-files DIR` for the command-line tests. */
static const tp_test_case tp_test_cases_[] = {TESTS(TP_TEST_CASE_)};

static int write_files(const char* dir)
{
    char path[512];
    size_t i;
    int failed = 0;
    if (mkdir(dir, 0700) != 0 && errno != EEXIST) {
        fprintf(stderr, "%s: %s\n", dir, strerror(errno));
        return 1;
    }
    for (i = 0; i < BAD_CASE_COUNT; ++i) {
        const bad_case* c = &bad_cases[i];
        snprintf(path, sizeof path, "%s/%s", dir, c->file);
        if (c->make == make_directory)
            rmdir(path); /* from an earlier run */
        if (!c->make(path)) {
            fprintf(stderr, "%s: cannot write %s\n", c->name, path);
            failed = 1;
        }
    }
    return failed;
}

int main(int argc, char** argv)
{
    if (argc == 3 && strcmp(argv[1], "--write-files") == 0)
        return write_files(argv[2]);
    return tp_test_run_(tp_test_cases_, sizeof tp_test_cases_ / sizeof tp_test_cases_[0], argc,
                        argv);
}
