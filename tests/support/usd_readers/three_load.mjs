// Loads a .usda or .usdz with three.js's USDLoader (npm `three`) and prints the meshes it
// built as one JSON line: node three_load.mjs NODE_MODULES FILE [faces]
// With `faces`, each triangle's normal (from its winding) and the UV at its centre too.
// No DOM here: the loader's images are read as bytes (a package's file through its blob:
// URL, a file beside the layer from disk) and sized from their PNG header.
import { readFileSync } from 'node:fs';
import { resolveObjectURL } from 'node:buffer';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const [modules, file, what] = process.argv.slice(2);
const url = (...parts) => pathToFileURL(path.join(modules, 'three', ...parts)).href;
const THREE = await import(url('build', 'three.module.js'));
const { USDLoader } = await import(url('examples', 'jsm', 'loaders', 'USDLoader.js'));

THREE.ImageLoader.prototype.load = function (src, onLoad, onProgress, onError) {
  const image = (bytes) => {
    const png = bytes.length > 24 && bytes[1] === 0x50 && bytes[2] === 0x4e && bytes[3] === 0x47;
    const v = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    onLoad({ src, bytes: bytes.length, width: png ? v.getUint32(16) : 0, height: png ? v.getUint32(20) : 0 });
  };
  if (src.startsWith('blob:')) {
    resolveObjectURL(src).arrayBuffer().then((b) => image(new Uint8Array(b)), onError);
    return;
  }
  try {
    image(new Uint8Array(readFileSync(src)));
  } catch (e) {
    onError(e);
  }
};

function describe(o) {
  const g = o.geometry, pos = g.attributes.position, uv = g.attributes.uv;
  const index = (k) => (g.index ? g.index.getX(k) : k);
  const corners = g.index ? g.index.count : pos.count;
  const points = new Set();
  for (let i = 0; i < pos.count; ++i) points.add(pos.getX(i) + ' ' + pos.getY(i) + ' ' + pos.getZ(i));
  const m = Array.isArray(o.material) ? o.material[0] : o.material;
  const map = m && m.map;
  const mesh = { name: o.name, faces: corners / 3, vertices: points.size, uvs: uv ? uv.count : 0,
                 material: m ? m.type : null, roughness: m ? m.roughness : null, metalness: m ? m.metalness : null,
                 map: map && map.image ? { width: map.image.width, height: map.image.height, flipY: map.flipY,
                                           colorSpace: map.colorSpace } : null };
  if (what === 'faces') {
    mesh.triangles = [];
    const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
    for (let f = 0; f < corners / 3; ++f) {
      const i = [index(3 * f), index(3 * f + 1), index(3 * f + 2)];
      a.fromBufferAttribute(pos, i[0]).applyMatrix4(o.matrixWorld);
      b.fromBufferAttribute(pos, i[1]).applyMatrix4(o.matrixWorld);
      c.fromBufferAttribute(pos, i[2]).applyMatrix4(o.matrixWorld);
      const n = new THREE.Vector3().subVectors(b, a).cross(new THREE.Vector3().subVectors(c, a)).normalize();
      const u = uv ? (uv.getX(i[0]) + uv.getX(i[1]) + uv.getX(i[2])) / 3 : 0;
      const v = uv ? (uv.getY(i[0]) + uv.getY(i[1]) + uv.getY(i[2])) / 3 : 0;
      mesh.triangles.push([n.x, n.y, n.z, u, v]);
    }
  }
  return mesh;
}

const data = readFileSync(file);
const input = path.extname(file).toLowerCase() === '.usdz'
  ? data.buffer.slice(data.byteOffset, data.byteOffset + data.byteLength)
  : data.toString('utf8');
new USDLoader().parse(input, path.dirname(path.resolve(file)) + '/', (group) => {
  group.updateMatrixWorld(true);
  const out = { meshes: [] };
  group.traverse((o) => { if (o.isMesh) out.meshes.push(describe(o)); });
  const box = new THREE.Box3().setFromObject(group);
  out.min = box.min.toArray();
  out.max = box.max.toArray();
  console.log('THREE ' + JSON.stringify(out));
}, (e) => {
  console.log('THREE ' + JSON.stringify({ error: String((e && e.message) || e) }));
  process.exitCode = 1;
});
