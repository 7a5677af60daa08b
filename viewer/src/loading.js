// Reading a file into memory with its progress, for the status line while a large run's .glb
// loads (hundreds of MB take tens of seconds): a served file (?file=) through the fetch's body
// stream, a dropped or picked one through FileReader's progress events.

/** Bytes as MB with one decimal. */
export const mb = (bytes) => `${(bytes / 1e6).toFixed(1)} MB`;

/** The status line while `name` loads: the bytes read and, when the size is known, of how many. */
export function loadingText(name, loaded, total) {
  const of = total > 0 ? ` of ${mb(total)} (${Math.min(100, Math.floor((100 * loaded) / total))} %)` : '';
  return `Loading ${name}: ${mb(loaded)}${of}…`;
}

/**
 * A fetch's body as an ArrayBuffer, calling onProgress(loaded, total) as it arrives (total: its
 * Content-Length, 0 when not given). With the length known the bytes go straight into one buffer
 * of that size: a second copy of a large file would double the page's memory for a moment.
 */
export async function readResponse(response, onProgress) {
  const total = Number(response.headers.get('Content-Length')) || 0;
  if (!response.body) return response.arrayBuffer();
  const reader = response.body.getReader();
  let whole = total > 0 ? new Uint8Array(total) : null;
  const parts = [];
  let loaded = 0;
  onProgress(0, total);
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    if (whole && loaded + value.length <= total) whole.set(value, loaded);
    else {
      // More than the Content-Length said (a compressed transfer): pieces, joined at the end.
      if (whole) parts.push(whole.subarray(0, loaded));
      whole = null;
      parts.push(value);
    }
    loaded += value.length;
    onProgress(loaded, total);
  }
  if (whole) return loaded === total ? whole.buffer : whole.slice(0, loaded).buffer;
  const out = new Uint8Array(loaded);
  let at = 0;
  for (const p of parts) { out.set(p, at); at += p.length; }
  return out.buffer;
}

/** A File's bytes as an ArrayBuffer, calling onProgress(loaded, total) as FileReader reads it. */
export function readFile(file, onProgress) {
  return new Promise((resolve, reject) => {
    const r = new FileReader();
    r.onprogress = (e) => onProgress(e.loaded, e.lengthComputable ? e.total : file.size);
    r.onload = () => resolve(r.result);
    r.onerror = () => reject(r.error ?? new Error('the file could not be read'));
    onProgress(0, file.size);
    r.readAsArrayBuffer(file);
  });
}

/**
 * Resolves once the browser has had the chance to paint (the status line) before a long task on
 * the main thread (parsing a large .glb); in a hidden tab, whose frames do not come, after 100 ms.
 */
export function nextPaint() {
  return Promise.race([
    new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0))),
    new Promise((r) => setTimeout(r, 100)),
  ]);
}
