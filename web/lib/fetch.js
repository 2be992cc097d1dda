// Fetching for every page and worker: bytes or text, or an Error that
// names what failed and the HTTP status (never a silent empty result).

/** The bytes at `url`; an Error naming the URL and HTTP status otherwise. */
export async function fetchBytes(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: HTTP ${r.status}`);
  return new Uint8Array(await r.arrayBuffer());
}

/** The text at `url`; an Error "<what>: HTTP <status>" otherwise. */
export async function fetchText(url, what) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${what}: HTTP ${r.status}`);
  return r.text();
}
