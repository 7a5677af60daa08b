// Per-vertex values to colours: the blue - white - red map of the fields PLY (sim/fields.hpp),
// from the 2nd to the 98th percentile, in linear RGB; a run's .glb holds the values and range.
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

/**
 * Per geometry, its colour attribute for a field's colours, and the values, low and high it holds
 * the colours of. One per geometry, rewritten in place: three.js uploads each attribute as a
 * buffer of its own and frees on geometry.dispose() only those of the geometry's current
 * attributes, so a new attribute per choice or frame would leave each one it replaced on the GPU.
 */
const fieldColours = new WeakMap();

/**
 * The geometry's colour attribute holding linear RGB colours for `values` mapped over [low, high]
 * (not yet set as its 'color': the caller does). The colours are written only when the values or
 * the range differ from those it holds (a frame or a choice changed), and uploaded again then.
 */
export function fieldColourAttribute(geometry, values, low, high) {
  let held = fieldColours.get(geometry);
  // A new attribute for values of another length: not expected (a field has one value per
  // vertex), but a short buffer would draw garbage.
  if (!held || held.attribute.count !== values.length) {
    const attribute = new THREE.BufferAttribute(new Float32Array(3 * values.length), 3);
    attribute.setUsage(THREE.DynamicDrawUsage);
    held = { attribute };
    fieldColours.set(geometry, held);
  }
  if (held.values === values && held.low === low && held.high === high) return held.attribute;
  const rgb = held.attribute.array;
  const c = new THREE.Color();
  for (let i = 0; i < values.length; i++) {
    const t = high > low ? Math.min(1, Math.max(0, (values[i] - low) / (high - low))) : 0.5;
    const r = t < 0.5 ? 2 * t : 1, g = t < 0.5 ? 2 * t : 2 * (1 - t), b = t < 0.5 ? 1 : 2 * (1 - t);
    c.setRGB(r, g, b, THREE.SRGBColorSpace);
    rgb[3 * i] = c.r; rgb[3 * i + 1] = c.g; rgb[3 * i + 2] = c.b;
  }
  Object.assign(held, { values, low, high });
  held.attribute.needsUpdate = true;
  return held.attribute;
}

/** The geometry's attribute of fieldColourAttribute, if it has one (for disposePane). */
export const fieldColoursOf = (geometry) => fieldColours.get(geometry)?.attribute;
