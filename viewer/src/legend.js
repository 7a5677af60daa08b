// The colour bar under the menu and the note's words for a field's scale (colour_map.js): its
// ends, 0 (a diverging map's white) and the units the CLI gives its fields (docs/cli.md, --fields).
import { cssGradient } from './colour_map.js';

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
  bar.querySelector('.ramp').style.background = cssGradient(scale.diverging);
  const f = (v) => Number(v.toPrecision(3)).toString();
  bar.querySelector('.low').textContent = f(scale.low);
  bar.querySelector('.mid').textContent = scale.diverging ? '0' : f((scale.low + scale.high) / 2);
  bar.querySelector('.high').textContent = f(scale.high);
  bar.querySelector('.units').textContent = `${name}${UNITS[name] ? ` ${UNITS[name]}` : ''}`;
}

/** The note's sentence for {name, scale, of} (`of`: what range the ends are). */
export function legendNote({ name, scale, of }) {
  return `${name}: ${scale.low.toPrecision(3)} to ${scale.high.toPrecision(3)}${UNITS[name] ? ` ${UNITS[name]}` : ''}; ` +
         `${scale.diverging ? 'blue below 0, white 0, red above' : 'dark purple low, yellow high'} ` +
         `(${of}${scale.diverging ? ', made symmetric about 0' : ''})`;
}
