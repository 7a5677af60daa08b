// Per-vertex values to colours: the blue - white - red map of the fields PLY and the glTF
// (src/export/field_colours.cpp), from the 2nd to the 98th percentile, in linear RGB.
import * as THREE from 'three';

/** The value at fraction q of the sorted values (nearest rank, as field_percentile). */
export function percentile(sorted, q) {
  if (!sorted.length) return 0;
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.round(q * (sorted.length - 1))))];
}

/** {low, high}: the 2nd and 98th percentiles of the finite values of all the arrays given. */
export function range(arrays) {
  const all = [];
  for (const a of arrays) for (const v of a) if (Number.isFinite(v)) all.push(v);
  all.sort((x, y) => x - y);
  return { low: percentile(all, 0.02), high: percentile(all, 0.98) };
}

/** A THREE.BufferAttribute of linear RGB colours for `values` mapped over [low, high]. */
export function colourAttribute(values, low, high) {
  const rgb = new Float32Array(3 * values.length);
  const c = new THREE.Color();
  for (let i = 0; i < values.length; i++) {
    const t = high > low ? Math.min(1, Math.max(0, (values[i] - low) / (high - low))) : 0.5;
    const r = t < 0.5 ? 2 * t : 1, g = t < 0.5 ? 2 * t : 2 * (1 - t), b = t < 0.5 ? 1 : 2 * (1 - t);
    c.setRGB(r, g, b, THREE.SRGBColorSpace);
    rgb[3 * i] = c.r; rgb[3 * i + 1] = c.g; rgb[3 * i + 2] = c.b;
  }
  return new THREE.BufferAttribute(rgb, 3);
}
