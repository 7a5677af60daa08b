// The colours the panes show: the colour menu's choices for the files open (a .glb's fields, a
// mesh file's own colours and scalar fields) with the first one, and a choice applied to every
// pane, each with its own values (main.js puts the result on the page: the colour bar, the note).
// A field is drawn on a diverging map about 0 or a sequential one (colour_map.js); a categorical
// one (a run's region ids) in a colour per id, with the ids as its legend.
import { colourScale, fieldColourAttribute, range } from './colour_map.js';
import { legendNote } from './legend.js';
import { paneKeyframe } from './frames.js';

/**
 * A file's header comments as a note: the first few, each cut to about a line, and how many more
 * (a result keeps its input's comments, so a PLY may hold thousands).
 * @param {string[]} comments
 */
function commentsNote(comments) {
  const cut = (c) => (c.length > 120 ? `${c.slice(0, 119)}\u2026` : c);
  const first = comments.slice(0, 3).map(cut).join('; ');
  return comments.length > 3 ? `${first}; and ${comments.length - 3} more comments` : first;
}

/**
 * The colour menu for the panes: `options` ([label, value]: 'none' is '-1', a glTF field its
 * index in `colourFields`, 'file' a mesh file's own colours, 'field:NAME' a mesh file's scalar
 * field), `colourFields` (the glTF fields by name: two runs may hold different ones) and `first`,
 * the choice a file opens on.
 */
export function colourChoices(panes) {
  // With none chosen, a file with materials wears them.
  const materials = panes.some((p) => p.looks?.some((l) => l.file));
  const options = [[materials ? 'none (file materials)' : 'none', '-1']];
  const glbs = panes.filter((p) => p.kind === 'glb');
  const colourFields = [...new Map(glbs.flatMap((p) => p.colourInfo).map((f) => [f.name, f])).values()];
  colourFields.forEach((f, i) => options.push([f.name, String(i)]));
  if (panes.some((p) => p.kind === 'mesh' && p.fileColours)) options.push(['file colours', 'file']);
  const names = [...new Set(panes.flatMap((p) => (p.kind === 'mesh' ? p.fields.map((f) => f.name) : [])))];
  names.forEach((n) => options.push([n, `field:${n}`]));
  // First choice: the files' materials where they have some (how the file says it looks; the
  // fields stay in the menu), else the glTF's first field, else the face colours of a file that
  // has them (a regions file: one colour a region), else the files' first field (one range over
  // the panes, so a --fields start and end pair compare: each file's baked colours are on its own
  // range), else the files' own colours.
  const values = options.map((o) => o[1]);
  const faceColours = panes.some((p) => p.kind === 'mesh' && p.faceColours);
  const firstField = values.find((v) => v.startsWith('field:'));
  const first = materials ? '-1' : values.includes('0') ? '0' : faceColours && values.includes('file') ? 'file'
    : firstField ?? (values.includes('file') ? 'file' : '-1');
  return { options, colourFields, first };
}

/**
 * Colours every pane by `choice` (a value of colourChoices' options), each with its own values
 * (those of the run frame `frame` for a .glb), or leaves it plain. `noFields`: the menu offers
 * nothing but 'none'. @returns {{shown: string[], values: (ArrayLike<number> | null)[],
 * legend: {name, scale, of} | null, notes: string[]}}: per pane, the colours it shows ('none', a
 * field's name, 'file colours' or 'file materials') and the values they show; the colour bar's
 * field and the note's sentences.
 */
export function applyColours(panes, { choice, colourFields, frame, noFields }) {
  const notes = [];
  // A scalar field of mesh files: one range over every pane that has it, so colours compare.
  const legends = [];  // {name, scale, of}: the colour bar's
  let scale = null;
  if (choice.startsWith('field:')) {
    const name = choice.slice(6);
    const arrays = panes.flatMap((p) => (p.kind === 'mesh' ? p.meshes.map((m) => m.geometry.userData.fields?.[name]).filter(Boolean) : []));
    const r = range(arrays);
    scale = colourScale(r.low, r.high);
    legends.push({ name, scale, of: `2nd to 98th percentile of ${panes.length > 1 ? 'both files: one range' : 'the file'}` });
  }
  const values = panes.map(() => null);  // per pane: the values its colours show, if any
  const shownOf = panes.map((p, pi) => {
    let shown = 'none', fileMaterials = false;
    p.meshes.forEach((m, j) => {
      let attr = null;
      if (p.kind === 'glb' && /^\d+$/.test(choice)) {
        const wanted = colourFields[Number(choice)];
        const i = p.colourInfo.findIndex((f) => f.name === wanted?.name), info = p.colourInfo[i];
        const k = paneKeyframe(p, frame), paneFrame = p.frameNumbers[k];
        const perFrame = info && p.frameFields[info.name];
        if (info?.categorical) {
          // Ids, not amounts: a colour each (grey for none), whatever the frame (a face's
          // region does not change as the shell moves).
          const scale = { categorical: true, ids: info.ids, none: Number(info.none ?? -1) };
          if (p.fieldValues[j][i]) {
            attr = fieldColourAttribute(m.geometry, p.fieldValues[j][i], scale);
            values[pi] = p.fieldValues[j][i];
          }
          if (j === 0) legends.push({ name: info.name, scale, of: 'a colour per id, as regions -o colours them' });
        } else if (perFrame) {
          // Each frame's own values, on one scale over all frames (so frames compare).
          const scale = colourScale(perFrame.low, perFrame.high);
          attr = fieldColourAttribute(m.geometry, perFrame.values[k], scale);
          values[pi] = perFrame.values[k];
          if (j === 0) legends.push({ name: info.name, scale, of: "each frame's own values; 2nd to 98th percentile over all frames" });
        } else if (info && (info.frame === undefined || info.frame === paneFrame) && p.fieldValues[j][i]) {
          // A field of one frame ('frame' in the extras) is shown on that frame only; without
          // 'frame', on any.
          attr = fieldColourAttribute(m.geometry, p.fieldValues[j][i], colourScale(Number(info.low), Number(info.high)));
          values[pi] = p.fieldValues[j][i];
        }
        if (info && !info.categorical && !perFrame && j === 0) {
          legends.push({ name: info.name, scale: colourScale(Number(info.low), Number(info.high)),
                         of: 'its 2nd to 98th percentile' + (info.frame !== undefined ? `; values of frame ${info.frame}, shown on that frame only` : '') });
        }
        if (attr) shown = info.name;
      } else if (p.kind === 'mesh' && choice === 'file' && p.fileColourAttributes[j]) {
        attr = p.fileColourAttributes[j];
        shown = 'file colours';
        // What the file's colours are: its header's comments say it where the CLI wrote them.
        if (j === 0) {
          notes.push(`${p.name}: its own ${p.faceColours ? 'face ' : ''}colours` +
                     (p.comments?.length ? ` (${commentsNote(p.comments)})` : '') +
                     (p.fields.length && !p.faceColours ? `, on its own scale; a field from the menu puts ${panes.length > 1 ? 'both files' : 'it'} on one` : ''));
        }
      } else if (p.kind === 'mesh' && scale) {
        const v = m.geometry.userData.fields?.[choice.slice(6)];
        if (v) {
          attr = fieldColourAttribute(m.geometry, v, scale);
          values[pi] = v;
          shown = choice.slice(6);
        }
      }
      // 'color' is the file's own attribute (on the GPU since the file opened) or the geometry's
      // one attribute of field colours (colour_map.js), rewritten there: a switch makes no buffer.
      if (attr) m.geometry.setAttribute('color', attr);
      // A field's colours when one is shown, else the file's material where it has one.
      const file = attr ? null : p.looks[j].file;
      m.material = file ?? p.looks[j].field;
      if (file) { fileMaterials = true; return; }
      const mat = m.material;
      mat.vertexColors = !!attr;
      mat.color.set(attr ? 0xffffff : 0xd8c8b0);
      mat.needsUpdate = true;
    });
    return shown === 'none' && fileMaterials ? 'file materials' : shown;
  });
  notes.push(...legends.map(legendNote));
  // The note says what is shown: a file with materials and no colour fields is not plain.
  const withMaterials = panes.filter((p, i) => shownOf[i] === 'file materials').map((p) => p.name);
  if (withMaterials.length) notes.push(`the materials of ${[...new Set(withMaterials)].join(' and ')} are shown`);
  if (noFields) notes.unshift(`no colour fields in ${panes.length > 1 ? 'these files' : 'this file'}`);
  return { shown: shownOf, values, legend: legends[0] ?? null, notes: [...new Set(notes)] };
}
