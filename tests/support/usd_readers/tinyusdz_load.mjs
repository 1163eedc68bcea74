// Loads a .usda or .usdz with TinyUSDZ (npm `tinyusdz`, its WebAssembly build) and prints
// what it read as one JSON line: node tinyusdz_load.mjs NODE_MODULES FILE [points]
// With `points`, each mesh's points and triangles as TinyUSDZ builds them for drawing (x, y, z,
// ...; three indices into them per face: a point is split where its corners' UVs differ).
// Textures beside a .usda are handed over as a web page would fetch them; TinyUSDZ decodes
// every texture itself.
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const [modules, file, what] = process.argv.slice(2);
// The npm build targets browsers and refuses to start in node: it is shown a window.
globalThis.window = globalThis;
process.type = 'renderer';
const dir = path.join(modules, 'tinyusdz');
const init = (await import(pathToFileURL(path.join(dir, 'tinyusdz.js')).href)).default;
const native = await init({ wasmBinary: readFileSync(path.join(dir, 'tinyusdz.wasm')) });
const bytes = new Uint8Array(readFileSync(file));

function load(assets) {
  const usd = new native.TinyUSDZLoaderNative();
  usd.setLoadTextureInNative(true);
  for (const [uri, data] of assets) usd.setAsset(uri, data);
  const ok = usd.loadFromBinary(bytes, path.basename(file));
  return { usd, ok };
}

// A first load names the textures the layer refers to; those not in a package are read
// from beside the layer for the second.
let { usd, ok } = load([]);
const missing = [];
for (let i = 0; ok && usd.getImage(i) && usd.getImage(i).uri; ++i)
  if (usd.getImage(i).bufferId < 0) missing.push(usd.getImage(i).uri);
if (missing.length) ({ usd, ok } = load(missing.map((u) => [u, new Uint8Array(readFileSync(path.join(path.dirname(file), u)))])));

const out = { ok, error: usd.error(), meshes: [], images: [] };
if (ok) {
  for (let i = 0; i < usd.numMeshes(); ++i) {
    const m = usd.getMesh(i);
    out.meshes.push({ name: m.primName, faces: m.faceVertexCounts.length, material: m.materialId,
                      texcoords: m.texcoords ? m.texcoords.length / 2 : 0,
                      ...(what === 'points' ? { points: Array.from(m.points), indices: Array.from(m.faceVertexIndices) } : {}) });
  }
  for (let i = 0; usd.getImage(i) && usd.getImage(i).uri; ++i) {
    const im = usd.getImage(i);
    out.images.push({ uri: im.uri, width: im.width, height: im.height, decoded: im.decoded, colorSpace: im.colorSpace });
  }
  const material = usd.getMaterial(0);
  out.texture = material && material.diffuseColorTextureId !== undefined ? material.diffuseColorTextureId : -1;
  // The layer as TinyUSDZ parsed it, for its metadata.
  const layer = new native.TinyUSDZLoaderNative();
  if (layer.loadAsLayerFromBinary(bytes, path.basename(file))) {
    const text = layer.layerToString();
    const meta = (key) => { const m = text.match(new RegExp('\\b' + key + ' = ("?[^"\\n]*"?)')); return m ? m[1] : null; };
    out.layer = { metersPerUnit: meta('metersPerUnit'), upAxis: meta('upAxis'), defaultPrim: meta('defaultPrim') };
  }
}
console.log('TINYUSDZ ' + JSON.stringify(out));
