// Per-vertex values to colours over a field's 2nd to 98th percentile (a run's .glb holds the
// values and that range), in linear RGB. A range across zero (a signed field: curvature, pressure)
// is made symmetric about 0 and drawn on a diverging map whose white is 0, so blue is negative and
// red positive, whatever the percentiles: with white at the range's middle the rest bear's convex
// vertices (H > 0) were mostly blue. A range on one side of zero (energy density) is drawn on a
// sequential map. Both maps are colour-blind safe (ColorBrewer's RdBu; viridis), and the ends of
// each stay apart in lightness as well as hue.
import * as THREE from 'three';

/** Stops (sRGB bytes), evenly spaced from the low end to the high end. */
const DIVERGING = [[33, 102, 172], [103, 169, 207], [247, 247, 247], [239, 138, 98], [178, 24, 43]];
const SEQUENTIAL = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];

/**
 * The scale a field's colours are drawn on, from its percentile range: {low, high, diverging}.
 * Across zero, symmetric about it (white is 0); else the range as given, on the sequential map.
 */
export function colourScale(low, high) {
  if (low < 0 && high > 0) {
    const m = Math.max(-low, high);
    return { low: -m, high: m, diverging: true };
  }
  return { low, high, diverging: false };
}

/** The sRGB colour (bytes) at t in [0, 1] of the map. */
export function mapColour(t, diverging) {
  const stops = diverging ? DIVERGING : SEQUENTIAL;
  const x = Math.min(1, Math.max(0, t)) * (stops.length - 1);
  const i = Math.min(stops.length - 2, Math.floor(x)), f = x - i;
  return stops[i].map((c, k) => c + f * (stops[i + 1][k] - c));
}

/**
 * The sRGB colour (bytes) of category `id` (a run's region id): grey for none (< 0), else the hue
 * id x the golden ratio (mod 1), as `shellcontract regions -o` colours a region's faces
 * (region_colour), so that a region has one colour in both files and ids next to each other are
 * far apart in hue.
 */
export function categoryColour(id) {
  if (!(id >= 0)) return [160, 160, 160];
  const hue = ((id * 0.6180339887498949) % 1) * 6;
  const v = 0.95, s = 0.85, sector = Math.floor(hue) % 6, frac = hue - Math.floor(hue);
  const p = v * (1 - s), q = v * (1 - s * frac), t = v * (1 - s * (1 - frac));
  const rgb = [[v, t, p], [q, v, p], [p, v, t], [p, q, v], [t, p, v], [v, p, q]][sector];
  return rgb.map((c) => Math.round(Math.min(1, Math.max(0, c)) * 255));
}

/** A CSS linear-gradient of the map, low to high (the colour bar). */
export const cssGradient = (diverging) =>
  `linear-gradient(to right, ${(diverging ? DIVERGING : SEQUENTIAL).map((c) => `rgb(${c.join(',')})`).join(', ')})`;

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
 * The geometry's colour attribute holding linear RGB colours for `values` mapped over the scale
 * (colourScale: its low, high and map; not yet set as its 'color': the caller does), or, for a
 * scale {categorical: true}, each value's categoryColour (ids, no range). The colours
 * are written only when the values or the scale differ from those it holds (a frame or a choice
 * changed), and uploaded again then.
 */
export function fieldColourAttribute(geometry, values, scale) {
  const { low, high, diverging } = scale, categorical = !!scale.categorical;
  let held = fieldColours.get(geometry);
  // A new attribute for values of another length: not expected (a field has one value per
  // vertex), but a short buffer would draw garbage.
  if (!held || held.attribute.count !== values.length) {
    const attribute = new THREE.BufferAttribute(new Float32Array(3 * values.length), 3);
    attribute.setUsage(THREE.DynamicDrawUsage);
    held = { attribute };
    fieldColours.set(geometry, held);
  }
  if (held.values === values && held.low === low && held.high === high && held.diverging === diverging &&
      held.categorical === categorical) return held.attribute;
  const rgb = held.attribute.array;
  const c = new THREE.Color();
  for (let i = 0; i < values.length; i++) {
    const t = high > low ? Math.min(1, Math.max(0, (values[i] - low) / (high - low))) : 0.5;
    const [r, g, b] = categorical ? categoryColour(Math.round(values[i])) : mapColour(t, diverging);
    c.setRGB(r / 255, g / 255, b / 255, THREE.SRGBColorSpace);
    rgb[3 * i] = c.r; rgb[3 * i + 1] = c.g; rgb[3 * i + 2] = c.b;
  }
  Object.assign(held, { values, low, high, diverging, categorical });
  held.attribute.needsUpdate = true;
  return held.attribute;
}

/** The geometry's attribute of fieldColourAttribute, if it has one (for disposePane). */
export const fieldColoursOf = (geometry) => fieldColours.get(geometry)?.attribute;
