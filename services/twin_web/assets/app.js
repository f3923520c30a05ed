// The live view: the selected asset group's state (Server-Sent Events from /api/events?group=ID, or polling
// /api/state?group=ID when a stream cannot be had) with the overview of every group (one status line each).
// The first response carries the state (twin-initial-state): the page is drawn before any event arrives.
// Text from the twin is always set as text, never as HTML.
'use strict';

(function () {
  const { node, utc, channelName, SEVERITY_RANK } = window.twinFormat;
  const panels = window.operatorPanels;
  const KNOWN_REC_FIELDS = new Set(['id', 'alarm_id', 'current', 'rank', 'target_channel', 'intervene_channel', 'delta',
    'effect_immediate', 'effect_steady_state', 'effect_low', 'effect_high', 'confidence', 'text', 'arrival',
    'answer_kind', 'horizon_snapshots', 'spectral_radius', 'draws', 'unstable_draws', 'unstable_draw_share',
    'effect_median', 'effect_percent', 'effect_percent_low', 'effect_percent_high', 'effect_level_change', 'reliable',
    'summary', 'action_kind']);
  const $ = (id) => document.getElementById(id);
  const urlGroup = new URLSearchParams(window.location.search).get('group');
  let state = null;     // {version, overview: {groups: [...]}, group: {...} | null}
  let selected = urlGroup;      // asset-group id shown (null: none yet)
  let chosen = urlGroup !== null;  // chosen by the link or the user (else the first group with data is followed)
  let started = false;  // the event stream is open (select() reconnects only then)
  let source = null;
  let polling = null;
  let points = 0;

  // "A. B." -> "A.": the headline of a long explanation (the rest stays available as the title).
  const firstSentence = (t) => { const s = String(t || ''); const m = /\.\s+(?=[A-Z[])/.exec(s); return m ? s.slice(0, m.index + 1) : s; };
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
    started = true;
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
    if (byUser) window.history.pushState({ group: id }, '', `?group=${encodeURIComponent(id)}`);
    const out = $('whatif-result');
    out.replaceChildren();
    out.dataset.status = 'idle';
    if (started) connect();  // the next event carries the new group
  }
  window.addEventListener('popstate', () => {
    const id = new URLSearchParams(window.location.search).get('group');
    if (id !== null) select(id, false);
  });

  // The root cause the operator should look at: the status line's, else the worst open degradation alarm's.
  function rootChannel(g) {
    if (g.status && g.status.state === 'alarm' && g.status.root_cause_channel) return g.status.root_cause_channel;
    const open = g.alarms.filter((a) => a.open && a.category === 'degradation' && a.root_cause_channel)
      .sort((a, b) => (SEVERITY_RANK[b.severity] || 0) - (SEVERITY_RANK[a.severity] || 0));
    return open.length ? open[0].root_cause_channel : 0;
  }

  function apply(s) {
    state = s;
    const groups = (s.overview && s.overview.groups) || [];
    const current = groups.find((x) => x.id === selected);
    if (!current || (!chosen && !current.has_trend)) {
      const first = groups.find((x) => x.has_trend) || groups[0];
      if (first && first.id !== selected && !chosen) select(first.id, false);
    }
    panels.renderOverview(groups, selected, (id) => select(id, true));
    const g = s.group && s.group.id === selected ? s.group : null;
    $('empty').hidden = !!g;
    $('view').hidden = !g;
    if (!g) {
      const info = (s.overview && s.overview.info) || {};
      $('empty').textContent = selected && chosen && !current
        ? `No asset group "${selected}" on DDS domain ${info.domain || '?'} (yet).`
        : `Waiting for data from the twin on DDS domain ${info.domain || '?'}\u2026`;
      return;
    }
    $('stamp').textContent = g.last ? `${g.id} \u00b7 latest snapshot ${utc(g.last.time_ms)}` : g.id;
    points = window.renderTrendChart($('trend'), g, $('band-note'));
    $('trend').dataset.points = String(points);
    const t = g.trend.time_ms;
    const info = (s.overview && s.overview.info) || {};
    $('trend-info').textContent = `${g.feature || ''} \u00b7 ${t.length} snapshots` +
      (t.length ? ` \u00b7 ${utc(t[0])} to ${utc(t[t.length - 1])}` : '');
    // Where the drawn history begins: the database (--db) or only what came since twin-web started.
    $('data-since').textContent = info.data_since || '';
    const root = rootChannel(g);
    const drawn = window.drawCausalGraph($('graph'), g.channels, g.graph, root);
    $('graph-info').textContent = g.graph.outcomes > 0 ? `${utc(g.graph.time_ms)} \u00b7 ${drawn} links` : '';
    panels.renderAlarms(g);
    panels.renderPrognoses(g);
    renderRecommendations(g);
    window.interventionPanel.render(g);
    renderWhatIfChannels(g);
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
      const approve = window.interventionPanel.approveBlock(r, g);
      if (approve) li.appendChild(approve);
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
  window.twinView = { pointCount: () => points, selected: () => selected, state: () => state, rootChannel: () => (state && state.group ? rootChannel(state.group) : 0) };
  // The state served with the page: drawn now, then kept current by the event stream.
  const initial = document.getElementById('twin-initial-state');
  let first = null;
  try { first = JSON.parse(initial ? initial.textContent : 'null'); } catch (e) { first = null; }
  if (first && first.overview) {
    if (selected === null && first.group) selected = first.group.id;
    apply(first);
    document.documentElement.dataset.initial = 'rendered';
  }
  connect();
})();
