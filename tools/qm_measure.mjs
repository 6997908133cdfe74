// qm_measure.mjs - the true error of a quantized-mesh tile set against a DEM's own posts, one
// measure for every tiler (tools/qm_compare.sh): each tile decoded by @here/quantized-mesh-decoder
// 1.2.8 (npm; written by HERE from the specification, sharing no code with any tiler measured),
// and for every DEM post inside the tile (its lon/lat from tools/qm_compare.py posts: GDAL/osr)
// the decoded TIN's height there (the triangle around the post, barycentric in u, v) against the
// post's height: per tile the maximum |difference|. Also: neighbouring tiles of a level sharing
// their side vertices (watertight).
//
//   node tools/qm_measure.mjs SET_DIR TILES.json POSTS.bin OUT.json
//
// TILES.json: {"tiles": [{"z", "x", "y", "bound"}, ...]} (the tiles to measure, the same list for
// every set). POSTS.bin: n float64 lon, then n float64 lat, then n float32 heights (metres), then
// n uint8 flags (1: the post's 8 neighbours are valid too), the DEM's valid posts. A post belongs to the tile that holds it, floor((lon + 180) / size) and
// floor((lat + 90) / size) (a post on a tile side to the east or north tile). OUT.json: per tile
// {z, x, y, bound, posts, max_error, max_error_inner (over the flagged posts), worst_at: [lat, lon, height] of the worst post,
// triangles, vertices, bytes}, and "pairs" / "watertight_pairs":
// neighbouring tile pairs of a level, and those whose shared side has the same vertices (also
// per level: "pairs_by_level": {z: [pairs, watertight pairs]}) (position
// along the side equal, decoded heights within 1 mm plus half of each tile's height step).
import { readFileSync, writeFileSync, statSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { gunzipSync } from 'node:zlib';

const MAXC = 32767;

function sideOf(t, k) { // [position along side k (west, south, east, north), height][] sorted
    const list = [t.west, t.south, t.east, t.north][k];
    const out = Array.from(list, (i) => [k === 0 || k === 2 ? t.v[i] : t.u[i], t.h[i]]);
    return out.sort((a, b) => a[0] - b[0]);
}

function decodeTile(decode, file) {
    const gz = readFileSync(file);
    const raw = gunzipSync(gz);
    const ab = raw.buffer.slice(raw.byteOffset, raw.byteOffset + raw.length);
    const d = decode(ab);
    const nv = d.vertexData.length / 3;
    const { minHeight: lo, maxHeight: hi } = d.header;
    const u = d.vertexData.subarray(0, nv), v = d.vertexData.subarray(nv, 2 * nv);
    const h = Float64Array.from(d.vertexData.subarray(2 * nv), (c) => lo + (hi - lo) * c / MAXC);
    return { u, v, h, tris: Uint32Array.from(d.triangleIndices), west: d.westIndices,
        south: d.southIndices, east: d.eastIndices, north: d.northIndices, bytes: gz.length,
        step: (hi - lo) / MAXC };
}

// max |TIN - post| over the n posts (pu, pv their u, v positions; ph their heights), the posts
// indexed by a grid of buckets over their own bounding box (a tile may hold the DEM in a corner)
function tileError(t, pu, pv, ph, inner) {
    const n = pu.length;
    if (n === 0) return { max: null, maxInner: null, unplaced: 0 };
    let u0 = Infinity, u1 = -Infinity, v0 = Infinity, v1 = -Infinity;
    for (let j = 0; j < n; ++j) {
        u0 = Math.min(u0, pu[j]); u1 = Math.max(u1, pu[j]); v0 = Math.min(v0, pv[j]); v1 = Math.max(v1, pv[j]);
    }
    const nb = Math.max(1, Math.min(1024, Math.round(Math.sqrt(n / 4))));
    const du = (u1 - u0) / nb || 1, dv = (v1 - v0) / nb || 1;
    const bu = (c) => Math.min(nb - 1, Math.max(0, Math.floor((c - u0) / du)));
    const bv = (c) => Math.min(nb - 1, Math.max(0, Math.floor((c - v0) / dv)));
    const cnt = new Int32Array(nb * nb + 1), bucket = new Int32Array(n);
    for (let j = 0; j < n; ++j) { bucket[j] = bv(pv[j]) * nb + bu(pu[j]); ++cnt[bucket[j] + 1]; }
    for (let b = 0; b < nb * nb; ++b) cnt[b + 1] += cnt[b];
    const pos = Int32Array.from(cnt), sorted = new Int32Array(n);
    for (let j = 0; j < n; ++j) sorted[pos[bucket[j]]++] = j;
    // best: the largest smallest barycentric weight so far (seen: any), err: the error there
    const err = new Float64Array(n), best = new Float64Array(n), seen = new Uint8Array(n);
    const { u, v, h, tris } = t;
    for (let k = 0; k < tris.length; k += 3) {
        const a = tris[k], b = tris[k + 1], c = tris[k + 2];
        const ua = u[a], va = v[a], ub = u[b], vb = v[b], uc = u[c], vc = v[c];
        const det = (ub - ua) * (vc - va) - (uc - ua) * (vb - va);
        const tu0 = Math.min(ua, ub, uc), tu1 = Math.max(ua, ub, uc);
        const tv0 = Math.min(va, vb, vc), tv1 = Math.max(va, vb, vc);
        if (det === 0 || tu1 < u0 || tu0 > u1 || tv1 < v0 || tv0 > v1) continue;
        const b0 = bu(tu0), b1 = bu(tu1);
        for (let r = bv(tv0), r1 = bv(tv1); r <= r1; ++r) {
            for (let q = cnt[r * nb + b0]; q < cnt[r * nb + b1 + 1]; ++q) {
                const j = sorted[q];
                const wb = ((pu[j] - ua) * (vc - va) - (uc - ua) * (pv[j] - va)) / det;
                const wc = ((ub - ua) * (pv[j] - va) - (pu[j] - ua) * (vb - va)) / det;
                const m = Math.min(1 - wb - wc, wb, wc);
                if (!seen[j] || m > best[j]) { // the triangle holding the post (or nearest to it)
                    best[j] = m; seen[j] = 1;
                    err[j] = Math.abs((1 - wb - wc) * h[a] + wb * h[b] + wc * h[c] - ph[j]);
                }
            }
        }
    }
    let max = 0, maxInner = 0, worst = 0, unplaced = 0;
    for (let j = 0; j < n; ++j) {
        if (!seen[j] || !(best[j] > -1e-6)) ++unplaced; // outside every triangle: a hole in the tile
        if (err[j] > max) { max = err[j]; worst = j; }
        if (inner[j] && err[j] > maxInner) maxInner = err[j];
    }
    return { max, maxInner, worst, unplaced };
}

async function main() {
    const [dir, listFile, postsFile, outFile] = process.argv.slice(2);
    if (!dir || !listFile || !postsFile || !outFile) {
        console.error('usage: node tools/qm_measure.mjs SET_DIR TILES.json POSTS.bin OUT.json');
        process.exit(2);
    }
    const npm = process.env.TP_NPM_DIR;
    if (!npm) throw new Error('TP_NPM_DIR is not set (run it through tools/qm_compare.sh)');
    const decode = (await import(pathToFileURL(join(npm,
        'node_modules/@here/quantized-mesh-decoder/src/index.js')).href)).default;
    const list = JSON.parse(readFileSync(listFile, 'utf8')).tiles;
    const pb = readFileSync(postsFile), n = pb.length / 21;
    if (!Number.isInteger(n)) throw new Error(`${postsFile}: ${pb.length} bytes, not 21 a post`);
    const ab = pb.buffer.slice(pb.byteOffset, pb.byteOffset + pb.length);
    const lon = new Float64Array(ab, 0, n), lat = new Float64Array(ab, 8 * n, n);
    const ph = new Float32Array(ab, 16 * n, n), inner = new Uint8Array(ab, 20 * n, n);
    const tiles = new Map(), out = [];
    for (const e of list) {
        const file = join(dir, `${e.z}/${e.x}/${e.y}.terrain`);
        statSync(file);
        tiles.set(`${e.z}/${e.x}/${e.y}`, { ...decodeTile(decode, file), e });
    }
    const levels = [...new Set(list.map((e) => e.z))];
    let unplacedAll = 0;
    for (const z of levels) { // the posts of each tile of the level, by a counting sort
        const size = 180 / 2 ** z, nx = 2 ** (z + 1), ny = 2 ** z, mine = list.filter((q) => q.z === z);
        const x0 = Math.min(...mine.map((q) => q.x)), y0 = Math.min(...mine.map((q) => q.y));
        const w = Math.max(...mine.map((q) => q.x)) - x0 + 1, hgt = Math.max(...mine.map((q) => q.y)) - y0 + 1;
        const slot = new Int32Array(n), count = new Int32Array(w * hgt + 1);
        for (let j = 0; j < n; ++j) {
            const x = Math.min(nx - 1, Math.floor((lon[j] + 180) / size)) - x0;
            const y = Math.min(ny - 1, Math.floor((lat[j] + 90) / size)) - y0;
            slot[j] = x >= 0 && x < w && y >= 0 && y < hgt ? y * w + x : -1;
            if (slot[j] >= 0) ++count[slot[j] + 1];
        }
        for (let b = 0; b < w * hgt; ++b) count[b + 1] += count[b];
        const at = Int32Array.from(count), order = new Int32Array(count[w * hgt]);
        for (let j = 0; j < n; ++j) if (slot[j] >= 0) order[at[slot[j]]++] = j;
        for (const e of mine) {
            const t = tiles.get(`${e.z}/${e.x}/${e.y}`), b = (e.y - y0) * w + (e.x - x0);
            const idx = order.subarray(count[b], count[b + 1]);
            const ws = -180 + e.x * size, ss = -90 + e.y * size;
            const m = idx.length, pu = new Float64Array(m), pv = new Float64Array(m);
            const hh = new Float64Array(m), fl = new Uint8Array(m); // (typed arrays' .from is slow)
            for (let q = 0; q < m; ++q) {
                const j = idx[q];
                pu[q] = (lon[j] - ws) / size * MAXC; pv[q] = (lat[j] - ss) / size * MAXC;
                hh[q] = ph[j]; fl[q] = inner[j];
            }
            const r = tileError(t, pu, pv, hh, fl);
            unplacedAll += r.unplaced;
            const wj = idx.length ? idx[r.worst] : -1;
            out.push({ z, x: e.x, y: e.y, bound: e.bound, posts: idx.length, max_error: r.max,
                max_error_inner: r.maxInner,
                worst_at: wj < 0 ? null : [lat[wj], lon[wj], ph[wj]],
                triangles: t.tris.length / 3, vertices: t.u.length, bytes: t.bytes });
        }
    }
    let pairs = 0, tight = 0;
    const byLevel = {}; // z: [pairs, watertight pairs]
    for (const [kk, t] of tiles) {
        const [z, x, y] = kk.split('/').map(Number);
        for (const [dx, dy, mine, theirs] of [[1, 0, 2, 0], [0, 1, 3, 1]]) {
            const o = tiles.get(`${z}/${x + dx}/${y + dy}`);
            if (!o) continue;
            ++pairs;
            byLevel[z] = byLevel[z] || [0, 0];
            ++byLevel[z][0];
            const a = sideOf(t, mine), b = sideOf(o, theirs), tol = 1e-3 + (t.step + o.step) / 2;
            if (a.length === b.length && a.every((p, i) => p[0] === b[i][0] && Math.abs(p[1] - b[i][1]) <= tol)) {
                ++tight;
                ++byLevel[z][1];
            }
        }
    }
    writeFileSync(outFile, JSON.stringify({ dir, posts: n, pairs, watertight_pairs: tight, pairs_by_level: byLevel,
        unplaced_posts: unplacedAll, tiles: out }));
}

main().catch((e) => { console.error(`qm_measure.mjs: ${e.message}`); process.exit(1); });
