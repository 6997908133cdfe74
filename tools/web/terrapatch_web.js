// tools/web/terrapatch_web.js - the page's module (index.html, docs/web.md): a quantized-mesh
// tile set of `terrapatch export --tiles quantized-mesh` in CesiumJS, with local imagery, from the
// camera `terrapatch view --camera-geo` takes, and every error Cesium reports collected.
//
// URL parameters (all optional):
//   tiles=URL            the tile set's folder (layer.json beside it; default "tiles/")
//   terrain=ellipsoid    draw the bare WGS84 ellipsoid instead (the test's reference picture)
//   imagery=URL          a TMS folder (gdal2tiles.py --profile geodetic); none: a plain base
//                        coloured and lit like a hillshade (sun from the north-west, 45 degrees)
//   camera-geo=LAT,LON,H,YAW,PITCH   as `terrapatch view --camera-geo`: WGS84 position, H metres
//                        above the DEM's vertical datum (the tile set's heights), YAW degrees
//                        clockwise from the render grid's north, PITCH degrees (-90 straight down)
//   grid=auto|true|ZONE  the north YAW counts from: auto (default) the UTM zone of the tile set's
//                        centre, the grid terrapatch renders a geographic DEM on; ZONE a UTM
//                        zone such as 10n or 31N; true: YAW is already from true north
//   fov=DEG              the vertical field of view (default 60, as `terrapatch view`)
//   fps=N                at most N frames a second (default: the browser's rate)
//   lean=1               no sky box, atmosphere, sun, moon or fog (a plain sky colour): 2.3x
//                        quicker to load on a software renderer (SwiftShader); the test uses it
//
// window.tpWeb (returned by start): errors (every tile, imagery, render and script error, as
// strings), ready (a promise: the viewer is made), waitLoaded(ms), sample([[lon, lat], ...]),
// viewer and info (what the page made of the parameters).
/* global Cesium */

const DEG = Math.PI / 180;

// Meridian convergence of transverse Mercator at (lat, lon) for central meridian lon0, in degrees:
// the angle from true north to grid north, counted clockwise (true bearing = grid bearing + it),
// as `terrapatch point` prints convergence_deg. The spherical formula; within 0.001 degrees of the
// ellipsoidal one inside a UTM zone.
export function convergenceDeg(latDeg, lonDeg, lon0Deg) {
  return Math.atan(Math.tan((lonDeg - lon0Deg) * DEG) * Math.sin(latDeg * DEG)) / DEG;
}

// The central meridian of a UTM zone given as "10n", "31S", "utm10n" or a number.
function zoneMeridian(zone) {
  const m = /^(?:utm)?\s*([0-9]{1,2})\s*[nsNS]?$/i.exec(String(zone).trim());
  if (!m || +m[1] < 1 || +m[1] > 60) return undefined;
  return -183 + 6 * +m[1];
}

// Parses "LAT,LON,H,YAW,PITCH" as `terrapatch view --camera-geo` does: five numbers.
export function parseCameraGeo(text) {
  const v = String(text).split(",").map((s) => Number(s.trim()));
  if (v.length !== 5 || v.some((x) => !Number.isFinite(x))) {
    throw new Error(`camera-geo: expected LAT,LON,H,YAW,PITCH (five numbers), got '${text}'`);
  }
  if (Math.abs(v[0]) > 90) throw new Error(`camera-geo: latitude ${v[0]} is outside [-90, 90]`);
  return { lat: v[0], lon: v[1], height: v[2], yaw: v[3], pitch: v[4] };
}

async function fetchJson(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: HTTP ${r.status}`);
  try {
    return await r.json();
  } catch (e) {
    throw new Error(`${url}: not JSON (${e.message})`);
  }
}

// The tile set's extent in degrees [W, S, E, N]: layer.json's bounds.
function boundsOf(layer) {
  const b = layer.bounds;
  if (Array.isArray(b) && b.length === 4 && b.every(Number.isFinite)) return b;
  return [-180, -90, 180, 90];
}

// A light from the north-west, 45 degrees up, over (lon, lat): a hillshade's sun.
function hillshadeLight(lon, lat) {
  const frame = Cesium.Transforms.eastNorthUpToFixedFrame(Cesium.Cartesian3.fromDegrees(lon, lat));
  const az = 315 * DEG, el = 45 * DEG;
  const toSunLocal = new Cesium.Cartesian3(Math.sin(az) * Math.cos(el), Math.cos(az) * Math.cos(el),
                                           Math.sin(el));
  const toSun = Cesium.Matrix4.multiplyByPointAsVector(frame, toSunLocal, new Cesium.Cartesian3());
  const dir = Cesium.Cartesian3.negate(Cesium.Cartesian3.normalize(toSun, toSun), toSun);
  return new Cesium.DirectionalLight({ direction: dir, intensity: 2.0 });
}

// The camera of camera-geo (true heading from the grid's yaw), or a view of the whole extent
// from the south, 50 degrees down, as `terrapatch view` starts.
function placeCamera(viewer, info, bounds) {
  const cam = viewer.camera;
  if (info.camera) {
    const c = info.camera;
    cam.setView({
      destination: Cesium.Cartesian3.fromDegrees(c.lon, c.lat, c.height),
      orientation: { heading: (c.yaw + info.convergenceDeg) * DEG, pitch: c.pitch * DEG, roll: 0 },
    });
    return;
  }
  const rect = Cesium.Rectangle.fromDegrees(...bounds);
  const centre = Cesium.Rectangle.center(rect);
  const size = Math.max(rect.width * Cesium.Ellipsoid.WGS84.maximumRadius * Math.cos(centre.latitude),
                        rect.height * Cesium.Ellipsoid.WGS84.maximumRadius);
  const range = Math.min((0.7 * size) / Math.tan((info.fovDeg / 2) * DEG), 2.0e7);
  const target = Cesium.Cartesian3.fromRadians(centre.longitude, centre.latitude, info.midHeight);
  cam.lookAt(target, new Cesium.HeadingPitchRange(0, -50 * DEG, range));
  cam.lookAtTransform(Cesium.Matrix4.IDENTITY);
}

// Cesium's fov is the horizontal one when the canvas is wider than high: keep the vertical one.
function keepVerticalFov(viewer, fovDeg) {
  viewer.scene.preRender.addEventListener((scene) => {
    const f = scene.camera.frustum;
    const w = scene.canvas.clientWidth, h = scene.canvas.clientHeight;
    if (!(f instanceof Cesium.PerspectiveFrustum) || !(w > 0 && h > 0)) return;
    const v = fovDeg * DEG;
    f.fov = w > h ? 2 * Math.atan(Math.tan(v / 2) * (w / h)) : v;
  });
}

function readParams(params, layer) {
  const bounds = boundsOf(layer);
  const midLon = (bounds[0] + bounds[2]) / 2, midLat = (bounds[1] + bounds[3]) / 2;
  const info = {
    tiles: params.get("tiles") || "tiles/",
    ellipsoid: params.get("terrain") === "ellipsoid",
    imagery: params.get("imagery") || "",
    fovDeg: Number(params.get("fov") || 60),
    grid: params.get("grid") || "auto",
    lean: params.get("lean") === "1",
    camera: params.get("camera-geo") ? parseCameraGeo(params.get("camera-geo")) : undefined,
    heights: (layer.terrapatch && layer.terrapatch.heights) || "unknown",
    midHeight: 0,
    convergenceDeg: 0,
  };
  if (!(info.fovDeg > 1 && info.fovDeg < 179)) throw new Error(`fov: ${params.get("fov")} is not 1..179 degrees`);
  const at = info.camera || { lat: midLat, lon: midLon };
  if (info.grid !== "true") {
    const zone = info.grid === "auto" ? Math.floor((midLon + 180) / 6) + 1 : info.grid;
    const lon0 = zoneMeridian(zone);
    if (lon0 === undefined) throw new Error(`grid: '${info.grid}' is not auto, true or a UTM zone (10n)`);
    info.convergenceDeg = convergenceDeg(at.lat, at.lon, lon0);
  }
  return { info, bounds };
}

async function makeViewer(container, info, bounds, errors) {
  const report = (what) => (e) => {
    errors.push(`${what}: ${e.message || e}${e.level !== undefined ? ` (tile ${e.level}/${e.x}/${e.y})` : ""}`);
    if (e.retry !== undefined) e.retry = false;
  };
  let terrainProvider;
  if (info.ellipsoid) {
    terrainProvider = new Cesium.EllipsoidTerrainProvider();
  } else {
    terrainProvider = await Cesium.CesiumTerrainProvider.fromUrl(info.tiles, { requestVertexNormals: true });
    terrainProvider.errorEvent.addEventListener(report("terrain"));
  }
  let baseLayer = false;
  if (info.imagery) {
    const provider = await Cesium.TileMapServiceImageryProvider.fromUrl(info.imagery);
    provider.errorEvent.addEventListener(report("imagery"));
    baseLayer = new Cesium.ImageryLayer(provider);
  }
  const viewer = new Cesium.Viewer(container, {
    terrainProvider, baseLayer, geocoder: false, baseLayerPicker: false, homeButton: false,
    sceneModePicker: false, navigationHelpButton: false, animation: false, timeline: false,
    fullscreenButton: false, infoBox: false, selectionIndicator: false, scene3DOnly: true,
    contextOptions: { webgl: { preserveDrawingBuffer: true } },
  });
  viewer.scene.renderError.addEventListener(report("render"));
  if (info.lean) {
    viewer.scene.skyBox.show = false;
    viewer.scene.skyAtmosphere.show = false;
    viewer.scene.sun.show = false;
    viewer.scene.moon.show = false;
    viewer.scene.fog.enabled = false;
    viewer.scene.globe.showGroundAtmosphere = false;
    viewer.scene.backgroundColor = Cesium.Color.fromCssColorString("#8fb3e6");
  }
  viewer.scene.globe.baseColor = Cesium.Color.fromCssColorString("#b8a98a");
  viewer.scene.globe.depthTestAgainstTerrain = true;
  if (!info.imagery) {
    viewer.scene.light = hillshadeLight((bounds[0] + bounds[2]) / 2, (bounds[1] + bounds[3]) / 2);
    viewer.scene.globe.enableLighting = true;
    viewer.scene.globe.dynamicAtmosphereLighting = false;
  }
  return viewer;
}

// Resolves once the globe has had nothing to load for `quiet` frames in a row; rejects after ms.
function waitLoaded(viewer, ms = 60000, quiet = 10) {
  return new Promise((resolve, reject) => {
    let n = 0;
    const t0 = performance.now();
    const off = viewer.scene.postRender.addEventListener(() => {
      n = viewer.scene.globe.tilesLoaded ? n + 1 : 0;
      if (n >= quiet) {
        off();
        resolve(performance.now() - t0);
      } else if (performance.now() - t0 > ms) {
        off();
        reject(new Error(`the globe's tiles did not finish loading in ${ms} ms`));
      }
    });
  });
}

// Cesium's most detailed height at each [lon, lat] (degrees), and the level of the tile it
// comes from (the tile set's availability). When a tile fails, each position is asked again
// alone: those of the failing tiles get height null and an error naming them.
async function sample(viewer, points, errors) {
  const tp = viewer.terrainProvider;
  const carto = points.map(([lon, lat]) => Cesium.Cartographic.fromDegrees(lon, lat));
  const levels = carto.map((c) =>
    tp.availability ? tp.availability.computeMaximumLevelAtPosition(c) : 0);
  const out = (c, i) => ({ lon: points[i][0], lat: points[i][1], height: c ? c.height : null, level: levels[i] });
  try {
    const got = await Cesium.sampleTerrainMostDetailed(tp, carto.map((c) => c.clone()), true);
    return got.map(out);
  } catch (e) {
    const one = [];
    for (let i = 0; i < carto.length; i++) {
      try {
        one.push((await Cesium.sampleTerrainMostDetailed(tp, [carto[i].clone()], true))[0]);
      } catch (f) {
        errors.push(`sample: no height at ${points[i][0]} ${points[i][1]} (level ${levels[i]}): ${f.message || f}`);
        one.push(undefined);
      }
    }
    return one.map(out);
  }
}

export function start(container, status, params) {
  const errors = [];
  const web = { errors, info: undefined, viewer: undefined };
  const say = (text, bad) => {
    status.textContent = text;
    status.className = bad ? "error" : "";
  };
  window.addEventListener("error", (e) => errors.push(`script: ${e.message}`));
  window.addEventListener("unhandledrejection", (e) => errors.push(`script: ${e.reason && e.reason.message || e.reason}`));
  web.ready = (async () => {
    const tiles = params.get("tiles") || "tiles/";
    const layer = await fetchJson(new URL("layer.json", new URL(tiles, window.location.href)).href);
    const { info, bounds } = readParams(params, layer);
    web.info = info;
    // no Cesium ion: no token, no default imagery, terrain or geocoder (every file is local)
    Cesium.Ion.defaultAccessToken = "";
    const viewer = await makeViewer(container, info, bounds, errors);
    if (params.get("fps")) viewer.targetFrameRate = Number(params.get("fps"));
    keepVerticalFov(viewer, info.fovDeg);
    placeCamera(viewer, info, bounds);
    web.viewer = viewer;
    web.waitLoaded = (ms, quiet) => waitLoaded(viewer, ms, quiet);
    web.sample = (points) => sample(viewer, points, errors);
    say(info.heights === "ellipsoid" && info.camera
      ? "heights above the ellipsoid: camera-geo's H is taken as ellipsoidal" : "");
    return info;
  })().catch((e) => {
    errors.push(`page: ${e.message || e}`);
    say(`terrapatch web: ${e.message || e}`, true);
    throw e;
  });
  web.ready.catch(() => {}); // rejected for whoever awaits it; said on the page and in errors
  return web;
}
