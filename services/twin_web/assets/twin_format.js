// Shared by the page's scripts: DOM nodes from text (never HTML) and the page's units: UTC times, hours, percent.
'use strict';

window.twinFormat = (function () {
  function node(tag, attrs, text) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, String(v));
    if (text !== undefined && text !== null) e.textContent = String(text);
    return e;
  }
  const iso = (ms) => new Date(ms).toISOString();
  // "2004-02-19 06:22 UTC": every time on the page is UTC, said so.
  const utc = (ms) => (ms ? iso(ms).slice(0, 16).replace('T', ' ') + ' UTC' : '');
  const utcShort = (ms) => (ms ? iso(ms).slice(0, 16).replace('T', ' ') : '');
  const finite = (v) => v !== null && v !== undefined && isFinite(v);
  // 0.5 h as "30 min", 7.25 as "7.3 h", 31.6 as "32 h".
  function hours(h) {
    if (!finite(h)) return 'unknown';
    if (h < 1) return `${Math.max(1, Math.round(60 * h))} min`;
    return `${h < 10 ? h.toFixed(1) : Math.round(h)} h`;
  }
  const channelName = (g, c) => (g.channels[c - 1] !== undefined ? g.channels[c - 1] : `channel ${c}`);
  const SEVERITY_RANK = { critical: 3, warning: 2, advisory: 1 };
  return { node, utc, utcShort, finite, hours, channelName, SEVERITY_RANK };
})();
