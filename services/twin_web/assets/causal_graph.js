// Draws the causal graph of one asset group as SVG: channels on a circle, an arrow j -> k for every
// significant link (|z| >= graph.min_z) of the condition-level filter, solid at once, dashed through the
// previous snapshot, width by |factor|, blue when j raises k and red when it lowers it. The root cause of the
// open alarms (1-based, 0 = none) gets a red ring and says so. No library needed.
'use strict';

window.drawCausalGraph = (function () {
  const NS = 'http://www.w3.org/2000/svg';
  const W = 440, H = 360, CX = W / 2, CY = H / 2 + 4, R = 130, NODE = 37;

  function el(name, attrs, text) {
    const e = document.createElementNS(NS, name);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, String(v));
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function marker(id, colour) {
    const m = el('marker', { id, viewBox: '0 0 10 10', refX: 9, refY: 5, markerWidth: 6, markerHeight: 6, orient: 'auto-start-reverse' });
    m.appendChild(el('path', { d: 'M0,0 L10,5 L0,10 z', fill: colour }));
    return m;
  }

  return function draw(svg, channels, graph, rootCause) {
    while (svg.firstChild) svg.removeChild(svg.firstChild);
    const defs = el('defs');
    defs.appendChild(marker('arrow-pos', '#1f5fa8'));
    defs.appendChild(marker('arrow-neg', '#c0392b'));
    svg.appendChild(defs);
    const n = channels.length;
    if (n === 0) {
      svg.appendChild(el('text', { x: CX, y: CY, 'text-anchor': 'middle', class: 'muted', fill: '#5d6878' }, 'no channels yet'));
      return 0;
    }
    const pos = channels.map((_, i) => {
      const a = -Math.PI / 2 + (2 * Math.PI * i) / n;
      return { x: CX + R * Math.cos(a), y: CY + R * Math.sin(a) };
    });
    const edges = (graph && graph.edges ? graph.edges : []).filter((e) => e.significant);
    const maxAbs = Math.max(0.25, ...edges.map((e) => Math.abs(e.factor)));
    for (const e of edges) {
      const a = pos[e.from - 1], b = pos[e.to - 1];
      if (!a || !b) continue;
      const dx = b.x - a.x, dy = b.y - a.y, len = Math.hypot(dx, dy) || 1;
      const ux = dx / len, uy = dy / len;
      // Start and end on the node rims; bend so j->k, k->j and the lagged link never lie on each other.
      const sx = a.x + ux * NODE, sy = a.y + uy * NODE, ex = b.x - ux * (NODE + 2), ey = b.y - uy * (NODE + 2);
      const bend = (e.lag === 0 ? 16 : 56);
      const mx = (sx + ex) / 2 - uy * bend, my = (sy + ey) / 2 + ux * bend;
      const colour = e.factor >= 0 ? '#1f5fa8' : '#c0392b';
      const width = 1.2 + 4.5 * Math.min(1, Math.abs(e.factor) / maxAbs);
      svg.appendChild(el('path', {
        d: `M${sx.toFixed(1)},${sy.toFixed(1)} Q${mx.toFixed(1)},${my.toFixed(1)} ${ex.toFixed(1)},${ey.toFixed(1)}`,
        fill: 'none', stroke: colour, 'stroke-width': width.toFixed(2), 'stroke-dasharray': e.lag === 0 ? '' : '6 4',
        'marker-end': `url(#${e.factor >= 0 ? 'arrow-pos' : 'arrow-neg'})`, opacity: 0.85, class: 'edge',
        'data-from': e.from, 'data-to': e.to, 'data-lag': e.lag,
      }));
      // Label on the curve (a quadratic Bezier's point at t), the lagged link's nearer its source, so the labels of
      // the links between one pair of channels stay apart; the line style already says which is lagged.
      const t = e.lag === 0 ? 0.55 : 0.4;
      const lx = (1 - t) * (1 - t) * sx + 2 * t * (1 - t) * mx + t * t * ex;
      const ly = (1 - t) * (1 - t) * sy + 2 * t * (1 - t) * my + t * t * ey;
      const label = (e.factor >= 0 ? '+' : '') + e.factor.toFixed(2) + (e.lag > 1 ? ` (lag ${e.lag})` : '');
      svg.appendChild(el('text', { x: lx.toFixed(1), y: (ly + 4).toFixed(1), 'text-anchor': 'middle', 'font-size': 11,
        fill: colour, stroke: '#fff', 'stroke-width': 3, 'paint-order': 'stroke' }, label));
    }
    const selfLags = new Map();
    for (const s of (graph && graph.self_lags) || []) {
      if (s.lag === 1) selfLags.set(s.to, s);
    }
    channels.forEach((name, i) => {
      const p = pos[i];
      const root = rootCause === i + 1;
      svg.appendChild(el('circle', { cx: p.x, cy: p.y, r: NODE, fill: root ? '#fde4e1' : '#eef3fa',
        stroke: root ? '#c0392b' : '#17324f', 'stroke-width': root ? 4 : 1.5,
        class: root ? 'node root-cause' : 'node', 'data-channel': i + 1 }));
      if (root) {  // above the node, or below it when above would leave the drawing
        const below = p.y - NODE - 6 < 10;
        svg.appendChild(el('text', { x: p.x, y: below ? p.y + NODE + 14 : p.y - NODE - 6, 'text-anchor': 'middle',
          'font-size': 11, 'font-weight': 700, fill: '#c0392b', class: 'root-cause-label' }, 'root cause'));
      }
      svg.appendChild(el('text', { x: p.x, y: p.y + 1, 'text-anchor': 'middle', 'font-size': 11, 'font-weight': 600, fill: '#17324f' }, name));
      const s = selfLags.get(i + 1);
      if (s) {
        svg.appendChild(el('text', { x: p.x, y: p.y + 14, 'text-anchor': 'middle', 'font-size': 9, fill: '#5d6878' },
          `self ${s.factor.toFixed(2)}`));
      }
    });
    if (edges.length === 0) {
      svg.appendChild(el('text', { x: CX, y: CY + 4, 'text-anchor': 'middle', 'font-size': 12, fill: '#5d6878' },
        graph && graph.outcomes > 0 ? `no link at |z| \u2265 ${graph.min_z}` : 'waiting for causal factors'));
    }
    return edges.length;
  };
})();
