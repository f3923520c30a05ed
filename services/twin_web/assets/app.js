// The live view: the selected asset group's state (Server-Sent Events from /api/events?group=ID, or polling
// /api/state?group=ID when a stream cannot be had) with the overview of every group for the group buttons.
// Text from the twin is always set as text, never as HTML.
'use strict';

(function () {
  const COLOURS = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#8c564b', '#e377c2'];
  const BAND = { advisory: 'rgba(240,190,30,0.14)', warning: 'rgba(240,130,30,0.16)', critical: 'rgba(215,40,40,0.18)' };
  const SEVERITY_RANK = { critical: 3, warning: 2, advisory: 1 };
  const KNOWN_REC_FIELDS = new Set(['id', 'alarm_id', 'current', 'rank', 'target_channel', 'intervene_channel', 'delta',
    'effect_immediate', 'effect_steady_state', 'effect_low', 'effect_high', 'confidence', 'text', 'arrival',
    'answer_kind', 'horizon_snapshots', 'spectral_radius', 'draws', 'unstable_draws', 'unstable_draw_share',
    'effect_median', 'effect_percent', 'effect_percent_low', 'effect_percent_high', 'effect_level_change', 'reliable',
    'summary']);
  const $ = (id) => document.getElementById(id);
  let state = null;     // {version, overview: {groups: [...]}, group: {...} | null}
  let selected = null;  // asset-group id shown (null: none yet)
  let chosen = false;   // the user picked it (else the first group with data is followed)
  let chart = null;
  let source = null;
  let polling = null;
  let points = 0;

  function node(tag, attrs, text) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, String(v));
    if (text !== undefined && text !== null) e.textContent = String(text);
    return e;
  }
  // "x; y; z" -> "x" and "A. B." -> "A.": the headline of a long explanation (the rest stays available).
  const firstClause = (t) => { const s = String(t || ''); const i = s.indexOf('; '); return i > 0 ? s.slice(0, i) : s; };
  const firstSentence = (t) => { const s = String(t || ''); const m = /\.\s+(?=[A-Z[])/.exec(s); return m ? s.slice(0, m.index + 1) : s; };
  const fmtTime = (ms) => (ms ? new Date(ms).toISOString().slice(0, 16).replace('T', ' ') + ' UTC' : '');
  const channelName = (g, c) => (g.channels[c - 1] !== undefined ? g.channels[c - 1] : `channel ${c}`);
  // Effects are in model units: log levels (estimator log_transform), shown as level changes in percent.
  const pct = (v) => (v === null || v === undefined || !isFinite(v) ? 'n/a'
    : `${v >= 0 ? '+' : ''}${(100 * Math.expm1(v)).toFixed(1)} %`);
  // A value that is already in percent (the recommender's effect_percent fields).
  // Beyond +1000 % a number says nothing more (a model that does not settle): capped as the twin's own text does.
  const percent = (v) => (v === null || v === undefined || !isFinite(v) ? 'n/a'
    : v > 1000 ? '> +1000 %' : `${v >= 0 ? '+' : ''}${v.toFixed(1)} %`);
  // "steady state", or "after H snapshots" when the model does not settle and the twin answers at a horizon.
  const answerLabel = (x) => (x.answer_kind === 'horizon' && x.horizon_snapshots ? `after ${x.horizon_snapshots} snapshots`
    : 'steady state');

  function setConn(text, live) {
    const c = $('conn');
    c.textContent = text;
    c.classList.toggle('live', live);
  }

  const groupQuery = () => `?group=${encodeURIComponent(selected === null ? '' : selected)}`;

  function connect() {
    if (source) { source.close(); source = null; }
    if (polling) { clearInterval(polling); polling = null; }
    if (!('EventSource' in window)) { poll(); return; }
    const es = new EventSource('/api/events' + groupQuery());
    source = es;
    es.addEventListener('state', (ev) => { if (es === source) { setConn('live', true); apply(JSON.parse(ev.data)); } });
    es.onerror = () => {
      if (es !== source) return;
      if (es.readyState === EventSource.CLOSED) { setConn('polling', false); poll(); } else { setConn('reconnecting', false); }
    };
  }

  function poll() {
    if (polling) return;
    const once = () => fetch('/api/state' + groupQuery(), { cache: 'no-store' })
      .then((r) => r.json()).then((s) => { setConn('polling', true); apply(s); })
      .catch(() => setConn('offline', false));
    once();
    polling = setInterval(once, 1000);
  }

  function select(id, byUser) {
    chosen = chosen || byUser;
    if (id === selected) return;
    selected = id;
    const out = $('whatif-result');
    out.replaceChildren();
    out.dataset.status = 'idle';
    connect();  // the next event carries the new group
  }

  function apply(s) {
    state = s;
    const groups = (s.overview && s.overview.groups) || [];
    const current = groups.find((x) => x.id === selected);
    if (!current || (!chosen && !current.has_trend)) {
      const first = groups.find((x) => x.has_trend) || groups[0];
      if (first && first.id !== selected) select(first.id, false);
    }
    renderNav(groups);
    const g = s.group && s.group.id === selected ? s.group : null;
    $('empty').hidden = !!g;
    $('view').hidden = !g;
    if (!g) {
      const info = (s.overview && s.overview.info) || {};
      $('empty').textContent = `Waiting for data from the twin on DDS domain ${info.domain || '?'}\u2026`;
      return;
    }
    renderStamp(g);
    renderStatus(g);
    renderTrend(g);
    renderGraph(g);
    renderAlarms(g);
    renderRecommendations(g);
    renderWhatIfChannels(g);
  }

  function renderNav(groups) {
    const nav = $('groups');
    const ids = groups.map((g) => g.id).join('\u0000');
    if (nav.dataset.ids !== ids) {
      nav.dataset.ids = ids;
      nav.replaceChildren(...groups.map((g) => {
        const b = node('button', { type: 'button', 'data-group': g.id }, g.id || '(twin)');
        b.appendChild(node('span', { class: 'badge' }));
        b.addEventListener('click', () => select(g.id, true));
        return b;
      }));
    }
    groups.forEach((g, i) => {
      const b = nav.children[i];
      b.classList.toggle('active', g.id === selected);
      const badge = b.lastChild;  // open alarms, coloured by the worst
      badge.textContent = g.open_alarms > 0 ? String(g.open_alarms) : '';
      badge.className = g.open_alarms > 0 ? `badge sev ${g.worst_severity}` : 'badge';
      b.dataset.state = g.state || '';
      b.title = g.state ? `${g.id}: ${g.state}` : g.id;
    });
  }

  // The recommender's operator line: learning n of N, healthy, stopped (an operating state) or alarm.
  function renderStatus(g) {
    const el = $('status');
    const s = g.status;
    el.dataset.state = s ? s.state : '';
    el.textContent = s ? `${s.state.toUpperCase()} \u00b7 ${s.text}` +
      (s.action ? ` \u00b7 advice: ${s.action}` : '') : 'no status from the alarm-recommender yet';
  }

  function renderStamp(g) {
    $('stamp').textContent = g.last ? `snapshot ${g.last.index} \u00b7 ${fmtTime(g.last.time_ms)}` : '';
  }

  // Log-axis labels at 1, 2, 3 and 5 times a power of ten (Chart.js's own skip 3, which leaves a narrow range
  // with one label); every label on a linear axis.
  function logTick(v) {
    if (this.type !== 'logarithmic') return Number(Number(v).toPrecision(3)).toString();
    const m = v / Math.pow(10, Math.floor(Math.log10(v)));
    return [1, 2, 3, 5].some((x) => Math.abs(m - x) < 1e-6) ? Number(Number(v).toPrecision(2)).toString() : '';
  }

  function union(spans) {
    const sorted = spans.map((b) => ({ from: b.from, to: b.to })).sort((a, b) => a.from - b.from);
    const out = [];
    for (const b of sorted) {
      const last = out[out.length - 1];
      if (last && b.from <= last.to) last.to = Math.max(last.to, b.to); else out.push(b);
    }
    return out;
  }

  const bandPlugin = {
    id: 'alarmBands',
    beforeDatasetsDraw(c) {
      const bands = c.$alarmBands || [];
      const x = c.scales.x, area = c.chartArea, ctx = c.ctx;
      const span = (b) => {
        const x0 = Math.max(area.left, x.getPixelForValue(b.from));
        const x1 = Math.min(area.right, x.getPixelForValue(b.to));
        return x1 < x0 ? null : [x0, Math.max(2, x1 - x0)];
      };
      ctx.save();
      // One layer per severity (the union of its alarms' spans), so overlapping alarms do not darken the plot.
      for (const severity of ['advisory', 'warning', 'critical']) {
        ctx.fillStyle = BAND[severity];
        for (const u of union(bands.filter((b) => b.severity === severity))) {
          const s = span(u);
          if (s) ctx.fillRect(s[0], area.top, s[1], area.bottom - area.top);
        }
      }
      for (const b of bands) {  // which channel: a strip in its colour along the top
        const s = span(b);
        if (!s) continue;
        ctx.fillStyle = COLOURS[(b.channel - 1) % COLOURS.length];
        ctx.fillRect(s[0], area.top + 4 * (b.channel - 1), s[1], 3);
      }
      ctx.restore();
    },
  };

  function renderTrend(g) {
    const t = g.trend;
    const n = t.index.length;
    points = n * g.channels.length;
    $('trend').dataset.points = String(points);
    $('trend-info').textContent = `${g.feature || ''} \u00b7 ${n} snapshots`;
    if (!window.Chart) { $('band-note').textContent = 'Chart.js is not installed (Debian package libjs-chart.js).'; return; }
    const datasets = g.channels.map((name, c) => ({
      label: name,
      data: t.index.map((x, i) => ({ x, y: t.values[c][i] })),
      borderColor: COLOURS[c % COLOURS.length],
      backgroundColor: COLOURS[c % COLOURS.length],
      borderWidth: 1.4, pointRadius: 0, tension: 0,
    }));
    const positive = t.values.every((v) => v.every((y) => y > 0));
    // A robust lower end (the 1st percentile): a stopped machine's last snapshot must not crush the axis.
    const all = t.values.flat().sort((a, b) => a - b);
    const p1 = all.length ? all[Math.floor(0.01 * all.length)] : undefined;
    const yMin = p1 === undefined ? undefined : (positive ? p1 * 0.8 : p1 - 0.05 * Math.abs(all[all.length - 1] - p1));
    const last = n > 0 ? t.index[n - 1] : 0;
    const bands = g.alarms.filter((a) => a.channel >= 1)
      .map((a) => ({ from: a.raised_index, to: a.cleared_index !== null ? a.cleared_index : last, severity: a.severity, channel: a.channel }));
    const timeOf = new Map(t.index.map((x, i) => [x, t.time_ms[i]]));
    if (!chart) {
      chart = new window.Chart($('trend'), {
        type: 'line',
        data: { datasets },
        options: {
          animation: false, parsing: false, normalized: true, maintainAspectRatio: false,
          interaction: { mode: 'nearest', axis: 'x', intersect: false },
          scales: {
            x: { type: 'linear', title: { display: true, text: 'snapshot' } },
            y: {
              type: positive ? 'logarithmic' : 'linear',
              title: { display: true, text: g.feature || 'condition' },
              ticks: { callback: logTick },
            },
          },
          plugins: { legend: { position: 'top' }, tooltip: { callbacks: {} } },
        },
        plugins: [bandPlugin],
      });
    } else {
      chart.data.datasets = datasets;
      chart.options.scales.y.type = positive ? 'logarithmic' : 'linear';
      chart.options.scales.y.title.text = g.feature || 'condition';
    }
    chart.options.scales.y.min = yMin;
    chart.options.plugins.tooltip.callbacks.title = (items) =>
      (items.length ? `snapshot ${items[0].parsed.x} \u00b7 ${fmtTime(timeOf.get(items[0].parsed.x))}` : '');
    chart.$alarmBands = bands;
    chart.update('none');
  }

  function renderGraph(g) {
    const drawn = window.drawCausalGraph($('graph'), g.channels, g.graph);
    $('graph-info').textContent = g.graph.outcomes > 0 ? `snapshot ${g.graph.index} \u00b7 ${drawn} links` : '';
  }

  function renderAlarms(g) {
    const open = g.alarms.filter((a) => a.open)
      .sort((a, b) => (SEVERITY_RANK[b.severity] || 0) - (SEVERITY_RANK[a.severity] || 0) || a.raised_index - b.raised_index);
    const body = $('alarms').tBodies[0];
    body.replaceChildren(...open.map((a) => {
      const tr = node('tr', { 'data-alarm-id': a.id });
      const sev = node('td');
      sev.appendChild(node('span', { class: `sev ${a.severity}` }, a.severity));
      tr.appendChild(sev);
      tr.appendChild(node('td', {}, a.channel_name || (a.channel ? channelName(g, a.channel) : a.category)));
      tr.appendChild(node('td', { title: fmtTime(a.raised_time_ms) }, `#${a.raised_index}`));
      tr.appendChild(node('td', {}, a.root_cause_channel ? (a.root_cause_name || channelName(g, a.root_cause_channel)) : '\u2014'));
      // The first clause says what happened; the whole reason (often a paragraph) opens on a click.
      const reason = node('td', { class: 'reason' });
      const details = node('details');
      details.appendChild(node('summary', {}, firstClause(a.reason)));
      details.appendChild(node('div', {}, a.reason));
      reason.appendChild(details);
      reason.appendChild(node('div', { class: 'muted' }, `${a.category} \u00b7 ${a.kind} \u00b7 ${a.id}`));
      tr.appendChild(reason);
      return tr;
    }));
    if (open.length === 0) {
      const tr = node('tr');
      tr.appendChild(node('td', { colspan: 5, class: 'muted' }, 'No open alarm.'));
      body.appendChild(tr);
    }
    const badge = $('alarm-count');
    badge.textContent = String(open.length);
    badge.classList.toggle('hot', open.length > 0);
    const closed = g.alarms.length - open.length;
    $('closed-note').textContent = closed > 0 ? `${closed} alarm${closed === 1 ? '' : 's'} cleared earlier (shaded on the trends).` : '';
  }

  function renderRecommendations(g) {
    const recs = g.recommendations.filter((r) => r.current)
      .sort((a, b) => a.alarm_id.localeCompare(b.alarm_id) || a.rank - b.rank).slice(0, 8);
    const list = $('recs');
    list.replaceChildren(...recs.map((r) => {
      const li = node('li', { 'data-recommendation-id': r.id });
      const text = r.text || `act on ${channelName(g, r.intervene_channel)}`;
      li.appendChild(node('div', { title: text }, firstSentence(text)));
      const inPercent = r.effect_percent !== undefined && r.effect_percent !== null;
      const effect = inPercent ? percent(r.effect_percent) : pct(r.effect_steady_state);
      const low = inPercent ? percent(r.effect_percent_low) : pct(r.effect_low);
      const high = inPercent ? percent(r.effect_percent_high) : pct(r.effect_high);
      const conf = r.confidence ? ` (${Math.round(100 * r.confidence)} % interval ${low} .. ${high})` : '';
      li.appendChild(node('div', { class: 'detail' },
        `rank ${r.rank}: act on ${channelName(g, r.intervene_channel)}; ${channelName(g, r.target_channel)} ${answerLabel(r)} ` +
        `${effect}${conf}` + (r.reliable === false ? ' \u00b7 no reliable lever' : '') +
        (r.alarm_id ? ` \u00b7 for ${r.alarm_id}` : '')));
      // Fields this page does not know yet (the data model grows): shown as they come.
      const extra = Object.entries(r).filter(([k, v]) => !KNOWN_REC_FIELDS.has(k) && v !== null && typeof v !== 'object');
      if (extra.length) li.appendChild(node('div', { class: 'detail' }, extra.map(([k, v]) => `${k}: ${v}`).join(' \u00b7 ')));
      return li;
    }));
    if (recs.length === 0) list.appendChild(node('li', { class: 'muted' }, 'No open alarm asks for action.'));
  }

  function renderWhatIfChannels(g) {
    const sel = $('whatif-channel');
    const key = g.id + '\u0000' + g.channels.join('\u0000');
    if (sel.dataset.key === key) return;
    const keep = sel.value;
    sel.dataset.key = key;
    sel.replaceChildren(...g.channels.map((name, i) => node('option', { value: i + 1 }, name)));
    if (keep && Number(keep) <= g.channels.length) sel.value = keep;
  }

  function showAnswer(a, g) {
    const out = $('whatif-result');
    out.replaceChildren();
    if (!a.answered) {
      out.dataset.status = 'no-reply';
      out.appendChild(node('p', { class: 'error' }, `No answer: ${a.error}`));
      return;
    }
    if (!a.ok) {
      out.dataset.status = 'refused';
      out.appendChild(node('p', { class: 'error' }, `The twin cannot answer: ${a.error}`));
      return;
    }
    out.dataset.status = 'answered';
    out.appendChild(node('p', { class: 'answer-text' }, a.text));
    const table = node('table', { class: 'answer' });
    const head = node('tr');
    const answered = a.sustained ? answerLabel(a) : 'in total';
    for (const h of ['channel', 'at once', answered, 'interval']) head.appendChild(node('th', {}, h));
    table.appendChild(head);
    const show = a.percent ? pct : (v) => (v === null ? 'n/a' : v.toPrecision(3));
    // The recommender's percent of each channel's current level when it gives one; else from the model's units.
    const hasPercent = Array.isArray(a.effect_percent) && a.effect_percent.length === a.effect_immediate.length;
    a.effect_immediate.forEach((v, k) => {
      const tr = node('tr');
      tr.appendChild(node('td', {}, channelName(g, k + 1)));
      tr.appendChild(node('td', {}, show(v)));
      if (hasPercent) {
        tr.appendChild(node('td', {}, percent(a.effect_percent[k])));
        tr.appendChild(node('td', {}, `${percent(a.effect_percent_low[k])} .. ${percent(a.effect_percent_high[k])}`));
      } else {
        tr.appendChild(node('td', {}, show(a.effect_steady_state[k])));
        tr.appendChild(node('td', {}, `${show(a.effect_low[k])} .. ${show(a.effect_high[k])}`));
      }
      table.appendChild(tr);
    });
    out.appendChild(table);
  }

  $('whatif').addEventListener('submit', async (ev) => {
    ev.preventDefault();
    const g = state && state.group && state.group.id === selected ? state.group : null;
    if (!g) return;
    const out = $('whatif-result');
    const button = $('whatif-ask');
    out.dataset.status = 'asking';
    out.textContent = 'asking the twin\u2026';
    button.disabled = true;
    const body = { asset_group: g.id, channel: Number($('whatif-channel').value), percent: Number($('whatif-percent').value),
      sustained: $('whatif-mode').value === 'sustained' };
    try {
      // The server refuses a state-changing request without this page's CSRF token (web_guard.hpp).
      const csrf = document.querySelector('meta[name="twin-csrf"]').content;
      const r = await fetch('/api/whatif', { method: 'POST',
        headers: { 'Content-Type': 'application/json', 'X-Twin-CSRF': csrf }, body: JSON.stringify(body) });
      showAnswer(await r.json(), g);
    } catch (e) {
      out.dataset.status = 'error';
      out.textContent = `No answer: ${e}`;
    } finally {
      button.disabled = false;
    }
  });

  // For tests and the curious: what the page shows, without scraping pixels.
  window.twinView = { pointCount: () => points, selected: () => selected, state: () => state };
  connect();
})();
