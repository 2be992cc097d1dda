// The API reference (scripts/api-docs.mjs, written into web/dist/api.html by
// scripts/build-site.sh) holds every exported class, interface and function
// of the package's type declarations and every member of each class and
// interface (issue 52). The declarations are read here another way: comments
// stripped, then each body split at its top-level semicolons.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { ROOT } from './chromium.mjs';
import { MODULES, render } from '../../scripts/api-docs.mjs';

/** { name: [member names] } of the classes and interfaces, and the functions' names. */
function declarations(text) {
  const src = text.replace(/\/\*[\s\S]*?\*\//g, '').replace(/\/\/.*$/gm, '');
  const out = { types: {}, functions: [] };
  for (const m of src.matchAll(/export\s+(?:declare\s+)?function\s+([A-Za-z_$][\w$]*)/g)) out.functions.push(m[1]);
  for (const m of src.matchAll(/export\s+(?:declare\s+)?(?:class|interface)\s+([A-Za-z_$][\w$]*)[^{]*\{/g)) {
    let i = m.index + m[0].length, depth = 0, stmt = '';
    const members = [];
    for (; i < src.length; i++) {
      const ch = src[i];
      if (depth === 0 && ch === '}') break;
      if ('({[<'.includes(ch)) depth++;
      else if (')}]>'.includes(ch) && !(ch === '>' && src[i - 1] === '=')) depth--;
      if (depth === 0 && (ch === ';' || ch === '\n') && stmt.trim()) {
        const name = /^(?:static\s+|readonly\s+)*([A-Za-z_$][\w$]*)/.exec(stmt.trim());
        if (name && !['private', 'free'].includes(name[1])) members.push(name[1]);
        stmt = '';
        continue;
      }
      stmt += ch;
    }
    out.types[m[1]] = [...new Set(members)];
  }
  return out;
}

test('the API reference holds every exported class, function and member', () => {
  const html = render();
  let checked = 0;
  for (const [mod, file] of MODULES) {
    const d = declarations(fs.readFileSync(path.join(ROOT, file), 'utf8'));
    assert.ok(Object.keys(d.types).length + d.functions.length > 0, `${file}: nothing declared?`);
    for (const f of d.functions.filter((f) => f !== '__wbg_init')) {
      assert.ok(html.includes(`id="${mod}:${f}"`), `${mod}: function ${f} is missing from the reference`);
      checked++;
    }
    for (const [name, members] of Object.entries(d.types)) {
      if (name === 'InitOutput') continue; // wasm-bindgen's loader internals
      assert.ok(html.includes(`id="${mod}:${name}"`), `${mod}: ${name} is missing from the reference`);
      for (const m of members) {
        assert.ok(html.includes(`id="${mod}:${name}.${m}"`), `${mod}: ${name}.${m} is missing from the reference`);
        checked++;
      }
    }
  }
  // the client's own calls, by name (the declarations could have lost them too)
  for (const m of ['create', 'synthesize', 'synthesizeFromBvh', 'fillGaps', 'retarget', 'importBvh', 'ik', 'terminate']) {
    assert.ok(html.includes(`id="deeprep/client.js:DeeprepClient.${m}"`), `DeeprepClient.${m}`);
  }
  assert.ok(checked > 150, `only ${checked} names checked`);
});

test('scripts/build-site.sh wrote the reference into web/dist', { skip: !fs.existsSync(path.join(ROOT, 'web/dist')) && 'SKIP: run scripts/build-site.sh first' }, () => {
  const html = fs.readFileSync(path.join(ROOT, 'web/dist/api.html'), 'utf8');
  assert.ok(html.includes('id="deeprep:Inbetweener.fillGaps"') && html.includes('id="deeprep/three.js:toThree"'));
});
