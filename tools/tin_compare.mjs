// tin_compare.mjs - one npm mesher on one height grid, for `terrapatch bench --static --compare`
// (app/bench/bench_static.c). Run by tools/tin_compare.sh, which installs the meshers; one node
// process per mesher and bound, so its peak RSS is that job's.
//
//   node tools/tin_compare.mjs delatin|martini GRID.f32 SIZE_X SIZE_Y RUNS OUT.mesh MAX_ERROR
//
// GRID.f32: SIZE_X x SIZE_Y float32 heights, row-major, little-endian, no voids (the bench writes
// it). TP_NPM_DIR: the folder holding node_modules (delatin@0.2.0, @mapbox/martini@0.2.0).
// Each run meshes the grid from scratch: delatin `new Delatin(data, w, h).run(e)`; martini
// `createTile(data).getMesh(e)` (the Martini object of the grid size, an index table shared by
// every tile of that size, is made once, untimed; martini needs SIZE_X = SIZE_Y = 2^k + 1).
// OUT.mesh, little-endian: 6 float64 (median ms over RUNS, median ms of martini's createTile
// part (0 for delatin), peak RSS MiB of this process (process.resourceUsage().maxRSS), RSS MiB
// before the first run (runtime + grid), runs, max error asked), then 2 uint32 (vertex count,
// triangle count), vertices as uint32 (x, y) grid positions, triangles as uint32 index triples.
// The bench measures the true error of the mesh itself.
import { readFileSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

const [mesher, file, w, h, runs, out, maxError] = [process.argv[2], process.argv[3],
    +process.argv[4], +process.argv[5], +process.argv[6], process.argv[7], +process.argv[8]];
if (!(mesher === 'delatin' || mesher === 'martini') || !file || !(w >= 2) || !(h >= 2) ||
    !(runs >= 1) || !out || !(maxError >= 0)) {
    console.error('usage: node tin_compare.mjs delatin|martini GRID.f32 W H RUNS OUT.mesh MAX_ERROR');
    process.exit(2);
}
const dir = process.env.TP_NPM_DIR;
if (!dir) {
    console.error('tin_compare.mjs: TP_NPM_DIR is not set (run it through tools/tin_compare.sh)');
    process.exit(2);
}
const buf = readFileSync(file);
if (buf.length !== 4 * w * h) {
    console.error(`tin_compare.mjs: ${file}: ${buf.length} bytes, expected ${4 * w * h} for ${w}x${h} float32`);
    process.exit(1);
}
const data = new Float32Array(buf.buffer, buf.byteOffset, w * h);
const mib = (b) => b / (1024 * 1024);
const median = (v) => { const s = [...v].sort((a, b) => a - b); return s[s.length >> 1]; };
const now = () => Number(process.hrtime.bigint()) / 1e6;

let mesh; // {coords: x,y pairs, triangles}
const ms = [], tileMs = [];
let baseRss;
if (mesher === 'delatin') {
    const Delatin = (await import(pathToFileURL(join(dir, 'node_modules/delatin/index.js')).href)).default;
    baseRss = mib(process.memoryUsage().rss);
    for (let r = 0; r < runs; ++r) {
        const t0 = now();
        const tin = new Delatin(data, w, h);
        tin.run(maxError);
        ms.push(now() - t0);
        tileMs.push(0);
        mesh = { coords: tin.coords, triangles: tin.triangles };
    }
} else {
    if (w !== h || ((w - 1) & (w - 2)) !== 0) {
        console.error(`tin_compare.mjs: martini needs a (2^k+1)^2 grid, got ${w}x${h}`);
        process.exit(1);
    }
    const require = createRequire(join(dir, 'node_modules/'));
    const Martini = require('@mapbox/martini');
    const martini = new Martini(w);
    baseRss = mib(process.memoryUsage().rss);
    for (let r = 0; r < runs; ++r) {
        const t0 = now();
        const tile = martini.createTile(data);
        const t1 = now();
        const m = tile.getMesh(maxError);
        ms.push(now() - t0);
        tileMs.push(t1 - t0);
        mesh = { coords: m.vertices, triangles: m.triangles };
    }
}
const coords = Uint32Array.from(mesh.coords), tris = Uint32Array.from(mesh.triangles);
const head = new Float64Array([median(ms), median(tileMs), mib(process.resourceUsage().maxRSS * 1024),
    baseRss, runs, maxError]);
const counts = new Uint32Array([coords.length / 2, tris.length / 3]);
writeFileSync(out, Buffer.concat([Buffer.from(head.buffer), Buffer.from(counts.buffer),
    Buffer.from(coords.buffer), Buffer.from(tris.buffer)]));
