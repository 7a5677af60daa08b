// What the tests read of the drawn page through window.viewer (the page's state): the panes'
// morph influences, the colours and materials they show, three.js's count of GPU objects.

/** Adds the tests' functions to `state`; `panes()` gives the panes shown, `renderer` draws them. */
export function exposeForTests(state, panes, renderer) {
  /** Per pane, per mesh (a glTF primitive each), its morph target influences. */
  state.influences = () => panes().map((p) => p.meshes.map((m) => Array.from(m.morphTargetInfluences ?? [])));
  /** Per pane, the mean red (linear) of the colours it shows; null for a plain pane. */
  state.colourMeans = () => panes().map((p) => {
    let sum = 0, n = 0;
    for (const m of p.meshes) {
      const c = m.material.vertexColors ? m.geometry.getAttribute('color') : null;
      if (!c) return null;
      for (let i = 0; i < c.count; i++) sum += c.getX(i);
      n += c.count;
    }
    return n ? sum / n : null;
  });
  /**
   * Per pane, per mesh, the vertices of its corners (its index) and the colour it shows at each
   * vertex (linear RGB, three numbers a vertex); null for a mesh without colours shown.
   */
  state.vertexColours = () => panes().map((p) => p.meshes.map((m) => {
    const c = m.material.vertexColors ? m.geometry.getAttribute('color') : null;
    return c ? { index: Array.from(m.geometry.index?.array ?? []), rgb: Array.from(c.array) } : null;
  }));
  /** three.js's count of the geometries and textures on the GPU (renderer.info.memory). */
  state.memory = () => ({ ...renderer.info.memory });
  /**
   * Per pane, per mesh, the material drawn (an array for an OBJ's mesh of several, one per group):
   * its name, colour (linear RGB), opacity, the size of its texture (null without), whether it
   * shows vertex colours.
   */
  const look = (material) => ({
    name: material.name, colour: material.color.toArray(), opacity: material.opacity,
    texture: material.map?.image ? [material.map.image.width, material.map.image.height] : null,
    vertexColors: material.vertexColors,
  });
  state.looks = () => panes().map((p) => p.meshes.map((m) => (Array.isArray(m.material) ? m.material.map(look) : look(m.material))));
}
