/* tin_voids.c - TP_TIN_CUT_VOIDS (tp_tin.h): the corners of the valid cells on a void's edge,
 * inserted first so that those cells are triangulated on their own, and the cut that then drops
 * the triangles over invalid cells with the vertices only they used. */
#include "tin_int.h"

/* Whether cell (cx, cy) (corners (cx, cy) .. (cx + 1, cy + 1)) has four valid corners; cells
 * outside the grid count as valid (the outline is no void's edge). */
static int cell_valid(const float* h, int w, int hg, int cx, int cy)
{
    if (cx < 0 || cy < 0 || cx >= w - 1 || cy >= hg - 1)
        return 1;
    const float* r0 = h + (size_t)cy * w + cx;
    const float* r1 = r0 + w;
    return r0[0] == r0[0] && r0[1] == r0[1] && r1[0] == r1[0] && r1[1] == r1[1];
}

int tp__tin_void_classes(const float* h, int w, int hg, uint8_t* cls)
{
    int any = 0;
    for (int cy = 0; cy < hg - 1; ++cy)
        for (int cx = 0; cx < w - 1; ++cx) {
            if (!cell_valid(h, w, hg, cx, cy))
                continue;
            int boundary = 0;
            for (int dy = -1; dy <= 1 && !boundary; ++dy)
                for (int dx = -1; dx <= 1 && !boundary; ++dx)
                    boundary = !cell_valid(h, w, hg, cx + dx, cy + dy);
            if (!boundary)
                continue;
            any = 1;
            uint8_t* c0 = cls + (size_t)cy * w + cx;
            c0[0] = c0[1] = c0[w] = c0[w + 1] = TIN_FORCE;
        }
    return any;
}

/* Drops the triangles over invalid cells (cut_voids) and the vertices no triangle uses. With
 * every corner of a valid cell next to an invalid one a vertex, those cells are triangulated on
 * their own (a unit square's circumcircle holds no other sample), so no triangle crosses from
 * invalid cells to valid ones: its centroid's cell says which side it is on. */
void tp__tin_cut_voids(tin_build* b, uint32_t* remap)
{
    size_t kept = 0;
    for (size_t t = 0; t < b->nt; ++t) {
        const uint32_t* v = b->T[t].v;
        int64_t sx = (int64_t)b->vx[2 * v[0]] + b->vx[2 * v[1]] + b->vx[2 * v[2]];
        int64_t sy = (int64_t)b->vx[2 * v[0] + 1] + b->vx[2 * v[1] + 1] + b->vx[2 * v[2] + 1];
        int cx = (int)tp__tin_floor_div(sx, 3), cy = (int)tp__tin_floor_div(sy, 3);
        cx = cx > b->w - 2 ? b->w - 2 : cx;
        cy = cy > b->hgt - 2 ? b->hgt - 2 : cy;
        if (!cell_valid(b->h, b->w, b->hgt, cx, cy))
            continue;
        b->T[kept++] = b->T[t];
    }
    b->nt = kept;
    /* vertices kept in their order: new index <= old, so the forward copy is safe */
    for (size_t i = 0; i < b->nv; ++i)
        remap[i] = UINT32_MAX;
    for (size_t t = 0; t < b->nt; ++t)
        for (int k = 0; k < 3; ++k)
            remap[b->T[t].v[k]] = 0;
    size_t nv = 0;
    for (size_t i = 0; i < b->nv; ++i) {
        if (remap[i] == UINT32_MAX)
            continue;
        remap[i] = (uint32_t)nv;
        b->vx[2 * nv] = b->vx[2 * i];
        b->vx[2 * nv + 1] = b->vx[2 * i + 1];
        b->vz[nv] = b->vz[i];
        ++nv;
    }
    for (size_t t = 0; t < b->nt; ++t)
        for (int k = 0; k < 3; ++k)
            b->T[t].v[k] = remap[b->T[t].v[k]];
    b->nv = nv;
}
