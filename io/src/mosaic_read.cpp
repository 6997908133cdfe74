/*
 * mosaic_read.cpp - tp_mosaic's rows: a window of rows read through GDAL (nodata and the rim
 * outside a warped source's hull made NaN) and, when voids are filled, a window grown until it
 * holds every void the rows touch whole (void_fill.hpp), the --fill-from source's rows beside.
 */
#include "mosaic.hpp"
#include "render_grid.hpp"
#include "void_fill.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

using tpio::fail;

namespace {

/* Rows y0 .. y0+rows-1 as read: nodata and the rim outside the hull become NaN; no filling. */
tp_status read_raw(tp_mosaic* m, int y0, int rows, float* heights, tp_error* err)
{
    tpio::QuietGdal quiet;
    CPLErrorReset();
    const CPLErr io = m->ds->GetRasterBand(1)->RasterIO(GF_Read, 0, y0, m->w, rows, heights, m->w,
                                                        rows, GDT_Float32, 0, 0, nullptr);
    const CPLErr last = CPLGetLastErrorType();
    if (io != CE_None || last == CE_Failure || last == CE_Fatal)
        return fail(err, TP_ERR_BAD_DATA,
                    "reading rows %d .. %d of the mosaic failed, a source is truncated or "
                    "corrupt (%s)",
                    y0, y0 + rows - 1, tpio::gdal_message().c_str());
    const size_t n = (size_t)rows * m->w;
    const float nd = m->nodata;
    const bool tag = m->has_nodata, nd_nan = std::isnan(nd), guess = m->int16_guess;
    const double z = m->z_to_m;
    for (size_t i = 0; i < n; i++) {
        float v = heights[i];
        if ((tag && (v == nd || (nd_nan && std::isnan(v)))) ||
            (guess && (v == -32768.0f || v == -32767.0f)) || std::isinf(v) || v == FLT_MAX ||
            v == -FLT_MAX)
            heights[i] = NAN;
        else if (z != 1.0)
            heights[i] = (float)(v * z); /* metres */
    }
    if (m->back)
        tpio::mask_outside_hull(*m->back, m->back_geographic, m->sgt, m->sw, m->sh, m->gt, m->w,
                                y0, rows, heights);
    return TP_OK;
}

/* Rows y0 .. y0+rows-1 of the --fill-from source on the grid (NaN: no data). */
tp_status read_other(tp_mosaic* m, int y0, int rows, float* out, tp_error* err)
{
    tpio::QuietGdal quiet;
    if (m->other->GetRasterBand(1)->RasterIO(GF_Read, 0, y0, m->w, rows, out, m->w, rows,
                                             GDT_Float32, 0, 0, nullptr) != CE_None)
        return fail(err, TP_ERR_BAD_DATA, "--fill-from: reading rows %d .. %d failed (%s)", y0,
                    y0 + rows - 1, tpio::gdal_message().c_str());
    tpio::fill_source_to_metres(out, (size_t)m->w * rows, m->other_unit);
    return TP_OK;
}

/* Rows y0 .. y1-1 as read (into z) and of the second source (into o, when there is one),
 * through the ring of rows read before (tp_mosaic::rc): what it holds is copied, the rest read
 * in runs and kept there. */
tp_status read_cached(tp_mosaic* m, int y0, int y1, float* z, float* o, tp_error* err)
{
    const size_t w = (size_t)m->w;
    if (m->rc_cap == 0) { /* the tallest crop a void may need and a band of 65 rows around it:
                           * 4 bytes a sample of a row where the window has 60 (mosaic.cpp) */
        const long long cap = std::min<long long>(m->h, (long long)m->fill_max_rows + 72);
        m->rc_cap = (int)cap;
        m->rc.assign((size_t)cap * w, 0.0f);
        if (m->other)
            m->rc_other.assign((size_t)cap * w, 0.0f);
        m->rc_row.assign((size_t)cap, -1);
    }
    auto slot = [&](int y) { return (size_t)(y % m->rc_cap); };
    for (int y = y0; y < y1;) {
        if (m->rc_row[slot(y)] == y) {
            std::memcpy(z + (size_t)(y - y0) * w, m->rc.data() + slot(y) * w, w * sizeof(float));
            if (o)
                std::memcpy(o + (size_t)(y - y0) * w, m->rc_other.data() + slot(y) * w,
                            w * sizeof(float));
            y++;
            continue;
        }
        int e = y + 1; /* a run of rows not held */
        while (e < y1 && m->rc_row[slot(e)] != e)
            e++;
        if (const tp_status st = read_raw(m, y, e - y, z + (size_t)(y - y0) * w, err))
            return st;
        if (o)
            if (const tp_status st = read_other(m, y, e - y, o + (size_t)(y - y0) * w, err))
                return st;
        for (int r = y; r < e; r++) {
            std::memcpy(m->rc.data() + slot(r) * w, z + (size_t)(r - y0) * w, w * sizeof(float));
            if (o)
                std::memcpy(m->rc_other.data() + slot(r) * w, o + (size_t)(r - y0) * w,
                            w * sizeof(float));
            m->rc_row[slot(r)] = r;
        }
        y = e;
    }
    return TP_OK;
}

/* Makes the window rows a .. b-1 (as read, and of the second source), keeping the rows the old
 * window shares with it. */
tp_status load_window(tp_mosaic* m, int a, int b, tp_error* err)
{
    const size_t w = (size_t)m->w;
    const int oa = m->win_y0, ob = m->win_y0 + m->win_rows;
    const int ka = std::max(a, oa), kb = std::min(b, ob); /* rows kept */
    const bool keep = m->win_rows > 0 && ka < kb;
    if (keep && ka == a && kb == b && oa == a && ob == b)
        return TP_OK;
    const bool two = (bool)m->other;
    std::vector<float> nw((size_t)(b - a) * w), no(two ? nw.size() : 0);
    auto rows_of = [&](std::vector<float>& v, int y) { return v.data() + (size_t)(y - a) * w; };
    if (keep) {
        std::memcpy(rows_of(nw, ka), m->win.data() + (size_t)(ka - oa) * w,
                    (size_t)(kb - ka) * w * sizeof(float));
        if (two)
            std::memcpy(rows_of(no, ka), m->win_other.data() + (size_t)(ka - oa) * w,
                        (size_t)(kb - ka) * w * sizeof(float));
    }
    const int ranges[2][2] = {{a, keep ? ka : b}, {keep ? kb : b, b}};
    for (const auto& r : ranges) {
        if (r[1] <= r[0])
            continue;
        if (const tp_status st =
                read_cached(m, r[0], r[1], rows_of(nw, r[0]), two ? rows_of(no, r[0]) : nullptr,
                            err))
            return st;
    }
    m->win.swap(nw), m->win_other.swap(no);
    m->win_y0 = a, m->win_rows = b - a;
    return TP_OK;
}

/* Rows y0 .. y0+rows-1 with their voids filled as tpio::fill_voids fills the whole grid. The
 * window grows until it holds whole, with its crop, every void reaching those rows that is to be
 * filled: a void cut by the window's edge widens it (doubling), one seen whole sets it to its
 * crop. A void whose crop would be taller than fill_max_rows (the memory given to the window)
 * stays, whichever rows are read, and is counted in too_large. Rows already in the window are
 * kept, not read again. */
tp_status read_filled(tp_mosaic* m, int y0, int rows, float* heights, uint8_t* filled,
                      tp_error* err)
{
    const int W = m->w, H = m->h;
    const size_t w = (size_t)W;
    int a = std::max(0, y0 - 2), b = std::min(H, y0 + rows + 2);
    std::vector<int> label;
    std::vector<size_t> stack;
    std::vector<uint8_t> large; /* per region of the last labelling: left for memory */
    for (;;) {
        if (const tp_status st = load_window(m, a, b, err))
            return st;
        /* the voids reaching the rows asked for */
        const float* z = m->win.data();
        label.assign(m->win.size(), -1);
        large.clear();
        int na = a, nb = b;
        for (size_t s0 = (size_t)(y0 - a) * w; s0 < (size_t)(y0 + rows - a) * w; s0++) {
            if (!std::isnan(z[s0]) || label[s0] >= 0)
                continue;
            const int id = (int)large.size();
            int x0 = W, x1 = -1, ry0 = INT_MAX, ry1 = -1;
            bool border = false;
            stack.assign(1, s0);
            label[s0] = id;
            while (!stack.empty()) {
                const size_t i = stack.back();
                stack.pop_back();
                const int x = (int)(i % w), y = a + (int)(i / w);
                x0 = std::min(x0, x), x1 = std::max(x1, x), ry0 = std::min(ry0, y), ry1 = std::max(ry1, y);
                border |= x == 0 || x == W - 1 || y == 0 || y == H - 1;
                const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
                for (int k = 0; k < 4; k++) {
                    if (nx[k] < 0 || nx[k] >= W || ny[k] < a || ny[k] >= b)
                        continue;
                    const size_t j = (size_t)(ny[k] - a) * w + nx[k];
                    if (label[j] < 0 && std::isnan(z[j]))
                        label[j] = id, stack.push_back(j);
                }
            }
            const int bw = x1 - x0 + 1, bh = ry1 - ry0 + 1;
            const bool too_big = tpio::fill_crop_rows(bw, bh) > m->fill_max_rows;
            large.push_back(!border && bw <= m->fill_max && bh <= m->fill_max && too_big);
            if (border || bw > m->fill_max || bh > m->fill_max || too_big)
                continue; /* stays, whatever more of it there is */
            const int reach = tpio::fill_reach(bw, bh), grow = std::max(b - a, 16);
            na = std::min(na, ry0 == a && a > 0 ? a - grow : ry0 - reach);
            nb = std::max(nb, ry1 == b - 1 && b < H ? b + grow : ry1 + reach + 1);
        }
        na = std::max(0, na), nb = std::min(H, nb);
        if (na == a && nb == b)
            break;
        a = std::min(a, na), b = std::max(b, nb);
    }
    const float* band = m->win.data() + (size_t)(y0 - a) * w;
    bool any_nan = false;
    for (const float v : m->win)
        if (std::isnan(v)) {
            any_nan = true;
            break;
        }
    if (!any_nan) { /* nothing to fill */
        std::memcpy(heights, band, (size_t)rows * w * sizeof(float));
        if (filled)
            std::memset(filled, 0, (size_t)rows * w);
        return TP_OK;
    }
    std::vector<float> z(m->win); /* the window stays as read: the next read reuses it */
    double gt[6];
    std::memcpy(gt, m->gt, sizeof gt);
    gt[3] += a * gt[5];
    tpio::FillSpec spec;
    spec.fill_max = m->fill_max;
    spec.max_rows = m->fill_max_rows;
    spec.other = m->other ? m->win_other.data() : nullptr;
    spec.rows_y0 = y0 - a, spec.rows_y1 = y0 + rows - a;
    tpio::VoidCounts counts;
    tp_status st = tpio::fill_voids(z.data(), W, b - a, gt, spec, a == 0, b == H, m->filled_mask,
                                    &counts, err);
    if (st != TP_OK)
        return st;
    std::memcpy(heights, z.data() + (size_t)(y0 - a) * w, (size_t)rows * w * sizeof(float));
    if (filled)
        std::memcpy(filled, m->filled_mask.data() + (size_t)(y0 - a) * w, (size_t)rows * w);
    for (int y = std::max(y0, m->counted_to); y < y0 + rows; y++)
        for (size_t x = 0; x < w; x++) {
            const size_t i = (size_t)(y - a) * w + x;
            m->filled += m->filled_mask[i];
            m->from_other += m->filled_mask[i] && spec.other && !std::isnan(spec.other[i]);
            m->too_large += label[i] >= 0 && large[label[i]];
        }
    m->counted_to = std::max(m->counted_to, y0 + rows);
    return TP_OK;
}

} // namespace

extern "C" tp_status tp_mosaic_read_rows(tp_mosaic* m, int y0, int rows, float* heights,
                                         size_t height_count, tp_error* err)
{
    return tp_mosaic_read_rows_filled(m, y0, rows, heights, height_count, nullptr, err);
}

extern "C" tp_status tp_mosaic_read_rows_filled(tp_mosaic* m, int y0, int rows, float* heights,
                                                size_t height_count, uint8_t* filled,
                                                tp_error* err)
{
    if (!m || !heights || y0 < 0 || rows < 1 || y0 + rows > m->h ||
        height_count < (size_t)rows * m->w)
        return fail(err, TP_ERR_INVALID_ARG, "mosaic: rows %d .. %d outside the grid's %d rows",
                    y0, y0 + rows - 1, m ? m->h : 0);
    try {
        if (m->fill_max > 0)
            return read_filled(m, y0, rows, heights, filled, err);
        if (filled)
            std::memset(filled, 0, (size_t)rows * m->w);
        return read_raw(m, y0, rows, heights, err);
    } catch (...) {
        return tpio::caught(err, "mosaic");
    }
}

extern "C" size_t tp_mosaic_filled_samples(const tp_mosaic* m) { return m ? m->filled : 0; }

extern "C" void tp_mosaic_get_voids(const tp_mosaic* m, tp_mosaic_voids* out)
{
    *out = tp_mosaic_voids{};
    if (!m)
        return;
    out->filled_samples = m->filled;
    out->filled_from_samples = m->from_other;
    out->too_large_samples = m->too_large;
    out->max_void_rows = m->fill_max > 0 ? m->fill_max_rows : 0;
}
