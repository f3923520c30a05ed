// What the operator reads: one status line per asset group (with ?group= links), the alarms by category with their
// time scale, UTC times and full reasons, the prognosis and the recommendations. Text is set as text, never HTML.
'use strict';

window.operatorPanels = (function () {
  const { node, utc, utcShort, finite, hours, channelName, SEVERITY_RANK } = window.twinFormat;
  const CATEGORY_ORDER = ['degradation', 'data_quality', 'health', 'operating_change'];
  const CATEGORY_TITLE = { degradation: 'Degradation: the machine', data_quality: 'Data quality: the measurement',
    health: 'Health: the twin itself', operating_change: 'Operating change (re-baselined, not a fault)' };
  const LEVEL_ORDER = { warning: 1, critical: 2, end_of_life: 3 };
  const levelName = (l) => String(l || '').replace(/_/g, ' ');

  const learningText = (s) => (s ? `${s.learning_seen} of ${s.learning_needed}` : '\u2014');

  // The overview: one row per group. A click on the link switches the view without a reload (the link stays a
  // real link: it can be copied, bookmarked, opened in a new tab).
  function renderOverview(groups, selected, onSelect) {
    const body = document.querySelector('#group-status tbody');
    body.replaceChildren(...groups.map((gr) => {
      const s = gr.status;
      const tr = node('tr', { 'data-group': gr.id, 'data-state': s ? s.state : '' });
      tr.classList.toggle('active', gr.id === selected);
      const link = node('a', { href: `?group=${encodeURIComponent(gr.id)}`, class: 'group-link' }, gr.id || '(twin)');
      link.addEventListener('click', (ev) => {
        if (ev.ctrlKey || ev.metaKey || ev.shiftKey || ev.button !== 0) return;
        ev.preventDefault();
        onSelect(gr.id);
      });
      const first = node('td');
      first.appendChild(link);
      tr.appendChild(first);
      const state = node('td');
      state.appendChild(node('span', { class: `state ${s ? s.state : 'none'}` }, s ? s.state : 'no status yet'));
      tr.appendChild(state);
      const worst = node('td');
      const sev = s && s.worst_severity ? s.worst_severity : null;
      if (sev) worst.appendChild(node('span', { class: `sev ${sev}` }, `${sev} \u00d7${s.open_alarms}`));
      else worst.textContent = '\u2014';
      tr.appendChild(worst);
      tr.appendChild(node('td', { class: 'root' }, s && s.root_cause_name ? s.root_cause_name : '\u2014'));
      tr.appendChild(node('td', { class: 'action' }, s && s.action ? s.action : '\u2014'));
      tr.appendChild(node('td', { class: 'prognosis' }, s && s.prognosis_text ? s.prognosis_text : '\u2014'));
      tr.appendChild(node('td', { class: 'learning' }, learningText(s)));
      tr.appendChild(node('td', { class: 'time' }, gr.last_time_ms ? utcShort(gr.last_time_ms) : '\u2014'));
      return tr;
    }));
    if (groups.length === 0) {
      const tr = node('tr');
      tr.appendChild(node('td', { colspan: 8, class: 'muted' }, 'No asset group has reported yet.'));
      body.appendChild(tr);
    }
  }

  // The live forecast for an alarm's next level (Prognosis topic), else the one carried by its latest event.
  function nextLevelText(a, g) {
    if (a.category !== 'degradation' || !a.next_level) return '\u2014';
    const p = (g.prognoses || []).find((x) => x.channel === a.channel && x.level === a.next_level);
    if (p) {
      if (p.reached) return `${levelName(p.level)}: reached`;
      if (!p.known) return `${levelName(p.level)}: time unknown`;
      return `${levelName(p.level)} in ${hours(p.hours)} (${hours(p.hours_low)}\u2013${hours(p.hours_high)}), ${utc(p.eta_ms)}`;
    }
    if (!finite(a.hours_to_next_level)) return `${levelName(a.next_level)}: time unknown`;
    const high = finite(a.hours_to_next_level_high) ? hours(a.hours_to_next_level_high) : 'unbounded';
    return `${levelName(a.next_level)} in ${hours(a.hours_to_next_level)} (${hours(a.hours_to_next_level_low)}\u2013${high}) at the last event`;
  }

  function alarmRow(a, g) {
    const tr = node('tr', { 'data-alarm-id': a.id, 'data-time-scale': a.time_scale, 'data-category': a.category });
    const sev = node('td');
    sev.appendChild(node('span', { class: `sev ${a.severity}` }, a.severity));
    tr.appendChild(sev);
    tr.appendChild(node('td', {}, a.channel_name || (a.channel ? channelName(g, a.channel) : a.category)));
    tr.appendChild(node('td', { class: 'scale' }, a.time_scale));
    tr.appendChild(node('td', { class: 'since', title: `evidence at index ${a.evidence_index}` }, utcShort(a.raised_time_ms)));
    const conf = finite(a.root_cause_confidence) && a.root_cause_channel ? ` (${a.root_cause_confidence.toFixed(2)})` : '';
    tr.appendChild(node('td', {}, a.root_cause_channel ? (a.root_cause_name || channelName(g, a.root_cause_channel)) + conf : '\u2014'));
    tr.appendChild(node('td', { class: 'next' }, nextLevelText(a, g)));
    // The whole reason, wrapped: nothing hidden behind a scroll bar or a click.
    const reason = node('td', { class: 'reason' });
    reason.appendChild(node('div', { class: 'reason-text' }, a.reason));
    if (a.action) reason.appendChild(node('div', { class: 'action' }, `Action: ${a.action}`));
    reason.appendChild(node('div', { class: 'muted' }, `${a.kind} \u00b7 ${a.id}`));
    if (window.alarmActions) reason.appendChild(window.alarmActions.block(a, g));
    tr.appendChild(reason);
    return tr;
  }

  // Open alarms, one section per category (the machine first), worst and oldest first inside each.
  function renderAlarms(g) {
    const open = g.alarms.filter((a) => a.open);
    const body = document.querySelector('#alarms tbody');
    const rows = [];
    const categories = [...new Set([...CATEGORY_ORDER, ...open.map((a) => a.category)])];
    for (const c of categories) {
      const these = open.filter((a) => a.category === c)
        .sort((a, b) => (SEVERITY_RANK[b.severity] || 0) - (SEVERITY_RANK[a.severity] || 0) || a.raised_time_ms - b.raised_time_ms);
      if (these.length === 0) continue;
      const head = node('tr', { class: 'section' });
      head.appendChild(node('th', { colspan: 7 }, `${CATEGORY_TITLE[c] || c} (${these.length})`));
      rows.push(head, ...these.map((a) => alarmRow(a, g)));
    }
    body.replaceChildren(...rows);
    if (open.length === 0) {
      const tr = node('tr');
      tr.appendChild(node('td', { colspan: 7, class: 'muted' }, 'No open alarm.'));
      body.appendChild(tr);
    }
    if (window.alarmActions) window.alarmActions.renderHealth(g);
    const badge = document.getElementById('alarm-count');
    badge.textContent = String(open.length);
    badge.classList.toggle('hot', open.length > 0);
    const closed = g.alarms.length - open.length;
    document.getElementById('closed-note').textContent =
      closed > 0 ? `${closed} alarm${closed === 1 ? '' : 's'} cleared earlier (shaded on the trends).` : '';
    return open.length;
  }

  function renderPrognoses(g) {
    const list = (g.prognoses || []).slice().sort((a, b) => a.channel - b.channel || LEVEL_ORDER[a.level] - LEVEL_ORDER[b.level]);
    const body = document.querySelector('#prognosis tbody');
    body.replaceChildren(...list.map((p) => {
      const tr = node('tr', { 'data-channel': p.channel, 'data-level': p.level });
      tr.appendChild(node('td', {}, p.channel_name || channelName(g, p.channel)));
      tr.appendChild(node('td', {}, `${levelName(p.level)} (${finite(p.level_ratio) ? p.level_ratio : '?'}\u00d7 baseline)`));
      const when = p.reached ? 'reached' : !p.known ? 'unknown'
        : `${hours(p.hours)} (${hours(p.hours_low)}\u2013${hours(p.hours_high)})`;
      tr.appendChild(node('td', { title: p.text }, when));
      tr.appendChild(node('td', {}, p.known && !p.reached ? utcShort(p.eta_ms) : '\u2014'));
      return tr;
    }));
    if (list.length === 0) {
      const tr = node('tr');
      tr.appendChild(node('td', { colspan: 4, class: 'muted' }, 'No open degradation alarm: nothing to forecast.'));
      body.appendChild(tr);
    }
    const at = list.length ? list[0].time_ms : 0;
    document.getElementById('prognosis-info').textContent = at ? `from ${utc(at)}` : '';
  }

  return { renderOverview, renderAlarms, renderPrognoses, levelName };
})();
