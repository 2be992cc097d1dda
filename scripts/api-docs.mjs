// The JavaScript API reference, one HTML page, from the package's type
// declarations (what an editor's user sees): web/pkg/deeprep.d.ts (the wasm
// API, written by wasm-bindgen from the Rust doc comments), web/client.d.ts
// (the worker client) and web/three.d.ts (the three.js helper). Every
// exported class, interface, function and type, with every member, its
// signature and its doc comment. scripts/build-site.sh writes it to
// web/dist/api.html; tests/web/api_docs.test.mjs checks nothing is missing.
// Usage: node scripts/api-docs.mjs OUT.html
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
export const MODULES = [
  ['deeprep', 'web/pkg/deeprep.d.ts', 'The page-side API: `import init, { ... } from \'deeprep\'` (call `await init()` first).'],
  ['deeprep/client.js', 'web/client.d.ts', 'The in-betweening client: a Web Worker behind promises, the models shipped in the package.'],
  ['deeprep/three.js', 'web/three.d.ts', 'three.js helpers: a synthesis result as a Skeleton and an AnimationClip.'],
];
// wasm-bindgen's loader internals, not API
const SKIP = new Set(['InitOutput', 'InitInput', 'SyncInitInput']);
const SKIP_MEMBER = /^(private constructor|free\(\): void|\[Symbol\.dispose\])/;

/** Doc comment text without the comment markers. */
function docText(lines) {
  return lines.join('\n').replace(/^\s*\/\*\*\s?/, '').replace(/\s*\*\/\s*$/, '')
    .split('\n').map((l) => l.replace(/^\s*\*\s?/, '')).join('\n').trim();
}

/** The declarations of a .d.ts text: [{ kind, name, doc, signature, members: [{ name, doc, signature }] }]. */
export function parseDts(text) {
  const lines = text.split('\n');
  const out = [];
  let doc = [], inDoc = false, cur = null, depth = 0, pending = null;
  const flushMember = () => {
    if (!pending) return;
    const sig = pending.lines.join(' ').replace(/\s+/g, ' ').trim();
    const m = /^(?:static\s+)?(?:readonly\s+)?(?:get\s+|set\s+)?([A-Za-z_$][\w$]*)\s*[?(:<]/.exec(sig);
    if (m && !SKIP_MEMBER.test(sig)) cur.members.push({ name: m[1], doc: pending.doc, signature: sig, static: /^static\s/.test(sig) });
    pending = null;
  };
  for (const line of lines) {
    const t = line.trim();
    if (inDoc || t.startsWith('/**')) {
      doc.push(line);
      inDoc = !t.endsWith('*/');
      continue;
    }
    if (t.startsWith('//') || t.startsWith('/*')) continue;
    if (depth === 0) {
      const m = /^export\s+(?:declare\s+)?(default\s+function|class|interface|function|type|const)\s+([A-Za-z_$][\w$]*)/.exec(t);
      if (m) {
        const kind = m[1].startsWith('default') ? 'function' : m[1];
        const name = m[1].startsWith('default') ? 'init (default export)' : m[2];
        cur = { kind, name, doc: docText(doc), signature: t, members: [] };
        if (!SKIP.has(m[2])) out.push(cur);
        if (kind === 'function' || kind === 'type' || kind === 'const') {
          // a signature may run over several lines
          if (!/;\s*$/.test(t)) { cur.open = true; depth = -1; }
          cur = kind === 'class' || kind === 'interface' ? cur : null;
        }
      }
      doc = [];
    } else if (depth === -1) {
      // continuation of a multi-line top-level signature
      const last = out[out.length - 1];
      last.signature += ` ${t}`;
      if (/;\s*$/.test(t)) { depth = 0; delete last.open; }
      continue;
    } else if (cur && (depth === 1 || pending)) {
      if (!pending && t && t !== '}') pending = { lines: [], doc: docText(doc) };
      if (pending) pending.lines.push(t);
      doc = [];
    }
    for (const ch of line.replace(/'[^']*'|"[^"]*"|`[^`]*`/g, '')) {
      if (ch === '{') depth++;
      else if (ch === '}') depth--;
    }
    if (pending && depth === 1 && /[;}]\s*$/.test(t) && balanced(pending.lines.join(' '))) flushMember();
    if (depth === 0 && cur && !cur.members.length && /\{.*\}/.test(t)) {
      // a one-line body: `export interface Progress { id: number; stage: string }`
      const inner = t.slice(t.indexOf('{') + 1, t.lastIndexOf('}'));
      for (const part of inner.split(';').map((x) => x.trim()).filter(Boolean)) {
        pending = { lines: [part + ';'], doc: '' };
        flushMember();
      }
    }
    if (depth === 0) { flushMember(); cur = null; }
  }
  return out;
}

function balanced(s) {
  let p = 0, b = 0;
  for (const ch of s) {
    if (ch === '(') p++; else if (ch === ')') p--;
    else if (ch === '{') b++; else if (ch === '}') b--;
  }
  return p === 0 && b === 0;
}

const esc = (s) => s.replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
const md = (s) => esc(s).replace(/`([^`]+)`/g, '<code>$1</code>').replace(/\n\s*\n/g, '</p><p>');

/** The reference page. */
export function render() {
  const version = JSON.parse(fs.readFileSync(path.join(ROOT, 'crate/Cargo.toml'), 'utf8').match(/^version\s*=\s*("[^"]+")/m)[1]);
  let body = '', toc = '';
  for (const [mod, file, about] of MODULES) {
    const decls = parseDts(fs.readFileSync(path.join(ROOT, file), 'utf8'));
    toc += `<li><a href="#${esc(mod)}">${esc(mod)}</a><ul>${decls.map((d) => `<li><a href="#${esc(mod)}:${esc(d.name)}">${esc(d.name)}</a></li>`).join('')}</ul></li>`;
    body += `<h2 id="${esc(mod)}">${esc(mod)}</h2><p>${md(about)}</p>`;
    for (const d of decls) {
      body += `<section id="${esc(mod)}:${esc(d.name)}"><h3>${d.kind} ${esc(d.name)}</h3>`;
      if (d.doc) body += `<p>${md(d.doc)}</p>`;
      if (!d.members.length) body += `<pre>${esc(d.signature)}</pre>`;
      for (const m of d.members) {
        body += `<div class="member" id="${esc(mod)}:${esc(d.name)}.${esc(m.name)}"><pre>${esc(m.signature)}</pre>${m.doc ? `<p>${md(m.doc)}</p>` : ''}</div>`;
      }
      body += '</section>';
    }
  }
  return `<!doctype html><meta charset="utf-8"><title>deeprep ${version}: JavaScript API</title>
<style>body{font:15px/1.5 system-ui,sans-serif;max-width:60em;margin:2em auto;padding:0 1em;color:#222}
pre{background:#f4f4f6;padding:.4em .6em;overflow-x:auto;margin:.3em 0}code{background:#f4f4f6}
section{border-top:1px solid #ddd;margin-top:1.2em}.member{margin-left:1.2em}h3{margin-bottom:.2em}</style>
<h1>deeprep ${version}: JavaScript API</h1>
<p>Generated from the package's type declarations by <code>scripts/api-docs.mjs</code>. The guide is the README.</p>
<ul>${toc}</ul>${body}\n`;
}

if (import.meta.url === `file://${process.argv[1]}`) {
  const out = process.argv[2];
  if (!out) { console.error('usage: node scripts/api-docs.mjs OUT.html'); process.exit(2); }
  for (const [, file] of MODULES) {
    if (!fs.existsSync(path.join(ROOT, file))) { console.error(`api-docs: ${file} is missing (build the wasm package first: bash scripts/build-wasm.sh)`); process.exit(1); }
  }
  fs.writeFileSync(out, render());
  console.log(`api-docs: wrote ${out}`);
}
