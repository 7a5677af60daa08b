// The colour bar under the menu and the note's words for a field's scale (colour_map.js): its
// ends, 0 (a diverging map's white) and the units the CLI gives its fields (docs/cli.md, --fields);
// for a categorical field (a run's region ids), a swatch per id instead of the ramp.
import { categoryColour, cssGradient } from './colour_map.js';

/** The most ids the bar shows a swatch of; the others are counted ("+ 12 more"). */
const MAX_SWATCHES = 32;

/** The units of the CLI's fields. */
export const UNITS = {
  mean_curvature: '(1/length of the input)', gaussian_curvature: '(1/length² of the input)',
  pressure: '(normalized units, > 0 pushes inward)', energy_density: '(normalized units)',
};

/** The bar (the #colour-bar element) for {name, scale}, or hidden for null. */
export function drawLegend(bar, legend) {
  bar.hidden = !legend;
  if (!legend) return;
  const { scale, name } = legend;
  // The swatches' row, made once beside the ramp; a ramp's legend hides it, a categorical one
  // the ramp and its ticks.
  let swatches = bar.querySelector('.swatches');
  if (!swatches) {
    swatches = document.createElement('div');
    swatches.className = 'swatches';
    bar.querySelector('.ramp').before(swatches);
  }
  const categorical = !!scale.categorical;
  swatches.hidden = !categorical;
  bar.querySelector('.ramp').hidden = categorical;
  bar.querySelector('.ticks').hidden = categorical;
  if (categorical) {
    swatches.replaceChildren(...[scale.none, ...scale.ids.slice(0, MAX_SWATCHES)].map((id) => {
      const s = document.createElement('span');
      s.className = 'swatch';
      s.dataset.id = String(id);
      s.style.background = `rgb(${categoryColour(id).join(',')})`;
      s.textContent = id < 0 ? 'none' : String(id);
      return s;
    }));
    if (scale.ids.length > MAX_SWATCHES) swatches.append(` + ${scale.ids.length - MAX_SWATCHES} more`);
    bar.querySelector('.units').textContent = `${name} ids`;
    return;
  }
  bar.querySelector('.ramp').style.background = cssGradient(scale.diverging);
  const f = (v) => Number(v.toPrecision(3)).toString();
  bar.querySelector('.low').textContent = f(scale.low);
  bar.querySelector('.mid').textContent = scale.diverging ? '0' : f((scale.low + scale.high) / 2);
  bar.querySelector('.high').textContent = f(scale.high);
  bar.querySelector('.units').textContent = `${name}${UNITS[name] ? ` ${UNITS[name]}` : ''}`;
}

/** The note's sentence for {name, scale, of} (`of`: what range the ends are). */
export function legendNote({ name, scale, of }) {
  if (scale.categorical) {
    const shown = scale.ids.slice(0, MAX_SWATCHES).join(', ') + (scale.ids.length > MAX_SWATCHES ? ', ...' : '');
    return `${name}: ${scale.ids.length} id${scale.ids.length === 1 ? '' : 's'} (${shown}); grey: none (${of})`;
  }
  return `${name}: ${scale.low.toPrecision(3)} to ${scale.high.toPrecision(3)}${UNITS[name] ? ` ${UNITS[name]}` : ''}; ` +
         `${scale.diverging ? 'blue below 0, white 0, red above' : 'dark purple low, yellow high'} ` +
         `(${of}${scale.diverging ? ', made symmetric about 0' : ''})`;
}
