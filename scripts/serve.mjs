// A tiny static file server for web/ on 127.0.0.1 (no dependencies).
// Usage: node scripts/serve.mjs [dir] [port]
// It also serves the shared data set's glTF files, read in place (never
// copied), at /shared-data/gltf/*.glb: from $DEEPREP_DATA, by default
// ../shared/data beside the served directory. The mesh page loads the robot
// from there; without it, the page asks for the file.
// Where web/pkg-core/ (the worker's smaller build) was not built, as after
// `scripts/build-wasm.sh --pages-only` (the demo's one build), its files are
// served from web/pkg/, the full package, which holds everything the worker
// imports; the relaxed-SIMD twin is then absent and the worker runs plain SIMD.
// web/vendor/three/ (three.js for the sketching page's glTF import) comes from
// node_modules/three/ where the site's copy is not there.
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';

const TYPES = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.wasm': 'application/wasm', '.json': 'application/json', '.onnx': 'application/octet-stream',
  '.css': 'text/css', '.png': 'image/png', '.bvh': 'text/plain', '.ts': 'text/plain',
  '.glb': 'model/gltf-binary',
};

/** `cors`: every answer allows any origin (a CDN's behaviour, for tests). */
export function serve(dir, port = 0, host = '127.0.0.1', { cors = false } = {}) {
  const root = path.resolve(dir);
  const data = path.resolve(process.env.DEEPREP_DATA || path.join(root, '..', 'shared', 'data'));
  const server = http.createServer((req, res) => {
    // A malformed request (bad percent-escape, odd URL) gets a 400, never
    // an exception that would stop the server.
    let pathname;
    try {
      pathname = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    } catch {
      res.writeHead(400); res.end('bad request'); return;
    }
    if (pathname.includes('\0')) { res.writeHead(400); res.end('bad request'); return; }
    let p;
    if (pathname.startsWith('/shared-data/gltf/') && pathname.endsWith('.glb')) {
      p = path.normalize(path.join(data, pathname.slice('/shared-data'.length)));
      if (!p.startsWith(path.join(data, 'gltf'))) { res.writeHead(403); res.end(); return; }
    } else {
      p = path.normalize(path.join(root, pathname));
      if (!p.startsWith(root)) { res.writeHead(403); res.end(); return; }
      const core = path.join(root, 'web', 'pkg-core');
      if (p.startsWith(core + path.sep) && !fs.existsSync(core)) {
        p = path.join(root, 'web', 'pkg', path.relative(core, p));
      }
      // three.js for the sketching page's glTF import: from node_modules
      // where the site's copy (scripts/build-site.sh) is not there
      const vendor = path.join(root, 'web', 'vendor', 'three');
      if (p.startsWith(vendor + path.sep) && !fs.existsSync(vendor)) {
        p = path.join(root, 'node_modules', 'three', path.relative(vendor, p));
      }
    }
    try {
      if (fs.existsSync(p) && fs.statSync(p).isDirectory()) p = path.join(p, 'index.html');
    } catch { /* unreadable: readFile below answers 404 */ }
    fs.readFile(p, (err, data) => {
      if (err) { res.writeHead(404); res.end('not found'); return; }
      res.writeHead(200, { 'Content-Type': TYPES[path.extname(p)] || 'application/octet-stream', 'Cache-Control': 'no-cache',
                           ...(cors ? { 'Access-Control-Allow-Origin': '*' } : {}) });
      res.end(data);
    });
  });
  return new Promise((resolve) => server.listen(port, host, () => resolve(server)));
}

if (import.meta.url === `file://${process.argv[1]}`) {
  const dir = process.argv[2] || '.';
  const port = Number(process.argv[3] || 8080);
  serve(dir, port).then((s) => console.log(`deeprep demo: http://127.0.0.1:${s.address().port}/web/ (serving ${path.resolve(dir)}; Ctrl-C stops)`));
}
