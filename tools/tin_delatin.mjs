// tin_delatin.mjs - delatin (mapbox, npm; greedy Delaunay insertion) on a height grid that
// tp_bench_tin wrote, for the side-by-side table in docs/PERFORMANCE.md ("Error-bounded TIN").
// Not vendored: install it next to this script's caller, e.g.
//   npm install --prefix /tmp/tin_delatin delatin@0.2.0
//   NODE_PATH=... is not used by ES modules: run with TP_DELATIN=/tmp/tin_delatin/node_modules/delatin/index.js
//
//   node tools/tin_delatin.mjs GRID.f32 WIDTH HEIGHT RUNS
// For e = 1, 5, 20 m writes GRID.f32.e<E>.mesh: median ms and peak RSS MiB (2 float64), then
// vertex and triangle counts (2 uint32), coords (x, y uint32 pairs), triangles (uint32 triples).
// The bench checks the true error of these meshes with its own checker.
import { readFileSync, writeFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

const [file, w, h, runs] = [process.argv[2], +process.argv[3], +process.argv[4], +(process.argv[5] || 3)];
const mod = process.env.TP_DELATIN || '/tmp/tin_delatin/node_modules/delatin/index.js';
const Delatin = (await import(pathToFileURL(mod).href)).default;
const buf = readFileSync(file);
const data = new Float32Array(buf.buffer, buf.byteOffset, w * h);
for (const e of [1, 5, 20]) {
    const ms = [];
    let tin;
    for (let r = 0; r < runs; ++r) {
        const t0 = process.hrtime.bigint();
        tin = new Delatin(data, w, h);
        tin.run(e);
        ms.push(Number(process.hrtime.bigint() - t0) / 1e6);
    }
    ms.sort((a, b) => a - b);
    const coords = Uint32Array.from(tin.coords), tris = Uint32Array.from(tin.triangles);
    const head = new Float64Array([ms[ms.length >> 1], process.resourceUsage().maxRSS / 1024]);
    const counts = new Uint32Array([coords.length / 2, tris.length / 3]);
    writeFileSync(`${file}.e${e}.mesh`, Buffer.concat([Buffer.from(head.buffer), Buffer.from(counts.buffer),
        Buffer.from(coords.buffer), Buffer.from(tris.buffer)]));
}
