// qm_tiler.mjs - a quantized-mesh tiler around an npm mesher, the way the web tilers built on
// @mapbox/martini (cesium-martini, the terrain-RGB tilers) and on delatin (kylebarron's
// quantized-mesh-encoder + pydelatin) work: per tile a 257 x 257 height grid over the tile,
// meshed at the level's error bound, encoded as quantized-mesh-1.0 with the octvertexnormals
// extension, gzip'd. Run by tools/qm_compare.sh (docs/PERFORMANCE.md, "Side by side with
// martini- and delatin-based tilers"); no complete tiler of that kind is installable here, so
// the part around the mesher (the encoder below, from the specification
// https://github.com/CesiumGS/quantized-mesh) is ours.
//
//   node tools/qm_tiler.mjs martini|delatin GRIDS.json GRIDS.f32 OUT_DIR
//
// GRIDS.json (tools/qm_compare.py grids): {"size": 257, "tiles": [{"z", "x", "y", "bound",
// "west", "south", "east", "north"}, ...]}; GRIDS.f32: one size x size float32 grid a tile, in
// that order, row 0 the north edge, column 0 the west edge (posts ON the tile's edges, so the
// two tiles of a side sample the same posts there). TP_NPM_DIR: the folder holding
// node_modules (delatin@0.2.0, @mapbox/martini@0.2.0). Writes OUT_DIR/Z/X/Y.terrain and
// OUT_DIR/stats.json: per tile {z, x, y, vertices, triangles, bytes, mesh_ms, encode_ms} (CPU
// milliseconds of this process: process.cpuUsage()), the sums, and the mesher. The Martini object (its index tables for the grid size, shared by every
// tile) is made once, untimed, as the tilers do.
import { readFileSync, openSync, readSync, closeSync, mkdirSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { gzipSync } from 'node:zlib';

const A = 6378137.0, F = 1 / 298.257223563, E2 = F * (2 - F), B = A * (1 - F);
const MAXC = 32767;

function ecef(lonDeg, latDeg, h) {
    const la = latDeg * Math.PI / 180, lo = lonDeg * Math.PI / 180;
    const n = A / Math.sqrt(1 - E2 * Math.sin(la) ** 2);
    return [(n + h) * Math.cos(la) * Math.cos(lo), (n + h) * Math.cos(la) * Math.sin(lo),
        (n * (1 - E2) + h) * Math.sin(la)];
}

// Cesium's EllipsoidalOccluder.computeMagnitude (scaled space): the distance along direction d
// of the horizon point that keeps scaled position p visible; null when none exists
function horizonMagnitude(p, d) {
    let m2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let m = Math.sqrt(m2);
    const dr = [p[0] / m, p[1] / m, p[2] / m];
    m2 = Math.max(1, m2); m = Math.max(1, m);
    const cosA = dr[0] * d[0] + dr[1] * d[1] + dr[2] * d[2];
    const cx = [dr[1] * d[2] - dr[2] * d[1], dr[2] * d[0] - dr[0] * d[2], dr[0] * d[1] - dr[1] * d[0]];
    const sinA = Math.hypot(cx[0], cx[1], cx[2]);
    const cosB = 1 / m, sinB = Math.sqrt(m2 - 1) * cosB;
    const den = cosA * cosB - sinA * sinB;
    return den > 0 ? 1 / den : null;
}

function octEncode(n) {
    const s = Math.abs(n[0]) + Math.abs(n[1]) + Math.abs(n[2]);
    let x = n[0] / s, y = n[1] / s;
    if (n[2] < 0) {
        const ox = x, oy = y;
        x = (1 - Math.abs(oy)) * (ox >= 0 ? 1 : -1);
        y = (1 - Math.abs(ox)) * (oy >= 0 ? 1 : -1);
    }
    const q = (c) => Math.round((Math.max(-1, Math.min(1, c)) * 0.5 + 0.5) * 255);
    return [q(x), q(y)];
}

// The header's sphere and horizon point, and the normals, from the decoded vertices
function geometry(t, u, v, hq, hmin, hmax, tris) {
    const nv = u.length, pos = new Array(nv);
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < nv; ++i) {
        const lon = t.west + (t.east - t.west) * u[i] / MAXC;
        const lat = t.south + (t.north - t.south) * v[i] / MAXC;
        pos[i] = ecef(lon, lat, hmin + (hmax - hmin) * hq[i] / MAXC);
        for (let k = 0; k < 3; ++k) { lo[k] = Math.min(lo[k], pos[i][k]); hi[k] = Math.max(hi[k], pos[i][k]); }
    }
    const c = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2];
    let r = 0;
    for (const p of pos) r = Math.max(r, Math.hypot(p[0] - c[0], p[1] - c[1], p[2] - c[2]));
    const sc = [c[0] / A, c[1] / A, c[2] / B], sl = Math.hypot(...sc);
    const d = sc.map((q) => q / sl);
    let mag = 0, ok = true;
    for (const p of pos) {
        const m = horizonMagnitude([p[0] / A, p[1] / A, p[2] / B], d);
        if (m === null) { ok = false; break; }
        mag = Math.max(mag, m);
    }
    if (!ok) mag = 1000; // no horizon point (a root tile): far out along the centre's direction
    const nrm = new Array(nv).fill(null).map(() => [0, 0, 0]);
    for (let k = 0; k < tris.length; k += 3) {
        const a = pos[tris[k]], b = pos[tris[k + 1]], q = pos[tris[k + 2]];
        const e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]], e2 = [q[0] - a[0], q[1] - a[1], q[2] - a[2]];
        const cr = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
        for (const i of [tris[k], tris[k + 1], tris[k + 2]]) for (let j = 0; j < 3; ++j) nrm[i][j] += cr[j];
    }
    const oct = new Uint8Array(2 * nv);
    for (let i = 0; i < nv; ++i) {
        let n = nrm[i];
        if (Math.hypot(...n) === 0) n = [pos[i][0] / A / A, pos[i][1] / A / A, pos[i][2] / B / B];
        const e = octEncode(n);
        oct[2 * i] = e[0]; oct[2 * i + 1] = e[1];
    }
    return { center: c, radius: r, horizon: d.map((q) => q * mag), oct };
}

// quantized-mesh-1.0 bytes of one tile: grid vertices (gx, gy on the size x size grid, gy = 0 the
// north row), their heights, triangles as index triples
export function encodeTile(t, size, gx, gy, hts, triIn) {
    const n0 = gx.length, cells = size - 1;
    // vertices in first-use order (high-water-mark coding needs it), triangles counter-clockwise
    const map = new Int32Array(n0).fill(-1), order = [];
    const tris = new Uint32Array(triIn.length);
    const cu = (i) => Math.round(gx[i] * MAXC / cells), cv = (i) => Math.round((cells - gy[i]) * MAXC / cells);
    for (let k = 0; k < triIn.length; k += 3) {
        let [a, b, c] = [triIn[k], triIn[k + 1], triIn[k + 2]];
        const cr = (cu(b) - cu(a)) * (cv(c) - cv(a)) - (cu(c) - cu(a)) * (cv(b) - cv(a));
        if (cr < 0) [b, c] = [c, b];
        for (const [j, i] of [[0, a], [1, b], [2, c]]) {
            if (map[i] < 0) { map[i] = order.length; order.push(i); }
            tris[k + j] = map[i];
        }
    }
    const nv = order.length;
    const u = new Uint16Array(nv), v = new Uint16Array(nv), hq = new Uint16Array(nv);
    let hmin = Infinity, hmax = -Infinity;
    for (const i of order) { hmin = Math.min(hmin, hts[i]); hmax = Math.max(hmax, hts[i]); }
    hmin = Math.fround(hmin); hmax = Math.fround(hmax);
    if (!(hmax > hmin)) hmax = Math.fround(hmin + 1);
    order.forEach((i, j) => {
        u[j] = cu(i); v[j] = cv(i);
        hq[j] = Math.max(0, Math.min(MAXC, Math.round((hts[i] - hmin) / (hmax - hmin) * MAXC)));
    });
    const g = geometry(t, u, v, hq, hmin, hmax, tris);
    const isz = nv > 65536 ? 4 : 2;
    const edges = [[], [], [], []]; // west, south, east, north, each sorted along its side
    for (let j = 0; j < nv; ++j) {
        if (u[j] === 0) edges[0].push(j);
        if (v[j] === 0) edges[1].push(j);
        if (u[j] === MAXC) edges[2].push(j);
        if (v[j] === MAXC) edges[3].push(j);
    }
    edges[0].sort((a, b) => v[a] - v[b]); edges[2].sort((a, b) => v[a] - v[b]);
    edges[1].sort((a, b) => u[a] - u[b]); edges[3].sort((a, b) => u[a] - u[b]);
    let len = 88 + 4 + 6 * nv;
    const pad = len % isz ? isz - (len % isz) : 0;
    len += pad + 4 + isz * tris.length;
    for (const e of edges) len += 4 + isz * e.length;
    len += 5 + 2 * nv;
    const buf = Buffer.alloc(len);
    let o = 0;
    const f64 = (x) => { buf.writeDoubleLE(x, o); o += 8; };
    const u32 = (x) => { buf.writeUInt32LE(x, o); o += 4; };
    const idx = (x) => { if (isz === 4) u32(x); else { buf.writeUInt16LE(x, o); o += 2; } };
    g.center.forEach(f64);
    buf.writeFloatLE(hmin, o); buf.writeFloatLE(hmax, o + 4); o += 8;
    g.center.forEach(f64); f64(g.radius);
    g.horizon.forEach(f64);
    u32(nv);
    for (const arr of [u, v, hq]) {
        let prev = 0;
        for (let j = 0; j < nv; ++j) {
            const dlt = arr[j] - prev;
            buf.writeUInt16LE(((dlt << 1) ^ (dlt >> 31)) & 0xffff, o); o += 2;
            prev = arr[j];
        }
    }
    o += pad;
    u32(tris.length / 3);
    let highest = 0;
    for (const i of tris) { idx(highest - i); if (i === highest) ++highest; }
    for (const e of edges) { u32(e.length); e.forEach(idx); }
    buf.writeUInt8(1, o); o += 1; u32(2 * nv);
    Buffer.from(g.oct.buffer).copy(buf, o); o += 2 * nv;
    if (o !== len) throw new Error(`encoder: wrote ${o} bytes of ${len}`);
    return { bytes: gzipSync(buf, { level: 6 }), vertices: nv, triangles: tris.length / 3 };
}

async function mesherFor(name, size) {
    const dir = process.env.TP_NPM_DIR;
    if (!dir) throw new Error('TP_NPM_DIR is not set (run it through tools/qm_compare.sh)');
    if (name === 'delatin') {
        const Delatin = (await import(pathToFileURL(join(dir, 'node_modules/delatin/index.js')).href)).default;
        return (grid, e) => {
            const tin = new Delatin(grid, size, size);
            tin.run(e);
            return { coords: tin.coords, triangles: tin.triangles };
        };
    }
    const Martini = createRequire(join(dir, 'node_modules/'))('@mapbox/martini');
    const martini = new Martini(size);
    return (grid, e) => {
        const m = martini.createTile(grid).getMesh(e);
        return { coords: m.vertices, triangles: m.triangles };
    };
}

async function main() {
    const [name, listFile, gridFile, out] = process.argv.slice(2);
    if (!(name === 'martini' || name === 'delatin') || !listFile || !gridFile || !out) {
        console.error('usage: node tools/qm_tiler.mjs martini|delatin GRIDS.json GRIDS.f32 OUT_DIR');
        process.exit(2);
    }
    const list = JSON.parse(readFileSync(listFile, 'utf8'));
    const size = list.size, cells = size * size;
    const mesh = await mesherFor(name, size);
    const fd = openSync(gridFile, 'r');
    const grid = new Float32Array(cells), raw = new Uint8Array(grid.buffer);
    const now = () => { const c = process.cpuUsage(); return (c.user + c.system) / 1e3; }; // CPU ms
    const stats = { mesher: name, size, tiles: [], mesh_ms: 0, encode_ms: 0, triangles: 0, bytes: 0 };
    list.tiles.forEach((t, k) => {
        if (readSync(fd, raw, 0, raw.length, k * raw.length) !== raw.length) {
            throw new Error(`${gridFile}: cut short at tile ${k}`);
        }
        const t0 = now();
        const m = mesh(grid, t.bound);
        const t1 = now();
        const nv = m.coords.length / 2, gx = new Array(nv), gy = new Array(nv), hts = new Float64Array(nv);
        for (let i = 0; i < nv; ++i) {
            gx[i] = m.coords[2 * i]; gy[i] = m.coords[2 * i + 1];
            hts[i] = grid[gy[i] * size + gx[i]];
        }
        const enc = encodeTile(t, size, gx, gy, hts, m.triangles);
        const t2 = now();
        mkdirSync(join(out, `${t.z}/${t.x}`), { recursive: true });
        writeFileSync(join(out, `${t.z}/${t.x}/${t.y}.terrain`), enc.bytes);
        stats.tiles.push({ z: t.z, x: t.x, y: t.y, vertices: enc.vertices, triangles: enc.triangles,
            bytes: enc.bytes.length, mesh_ms: t1 - t0, encode_ms: t2 - t1 });
        stats.mesh_ms += t1 - t0; stats.encode_ms += t2 - t1;
        stats.triangles += enc.triangles; stats.bytes += enc.bytes.length;
    });
    closeSync(fd);
    writeFileSync(join(out, 'stats.json'), JSON.stringify(stats));
}

main().catch((e) => { console.error(`qm_tiler.mjs: ${e.message}`); process.exit(1); });
