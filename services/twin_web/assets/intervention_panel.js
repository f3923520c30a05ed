// The closed loop on the page: the approve button under each recommended reliable lever (POSTed to /api/approve
// with the page's CSRF token, like the what-if form and the alarm actions; the approver is the authenticated
// operator), the group's approved interventions (who approved which lever, by how much, over which snapshots)
// and, once the window has passed, the twin's check of its own prediction: the predicted 90 % interval, the
// observed change, inside or not, improved or not, and the lever trust it left. Approvals also come from
// causal-approve (docs/advice.md). Text is set as text, never HTML.
'use strict';

window.interventionPanel = (function () {
  const { node, utc, finite } = window.twinFormat;
  const signed = (v) => (finite(v) ? `${v >= 0 ? '+' : ''}${v.toFixed(1)} %` : 'n/a');
  const named = (name, channel) => name || (channel ? `channel ${channel}` : '\u2014');

  function leverText(iv) {
    return `${named(iv.channel_name, iv.channel)} ${finite(iv.change_percent) ? signed(iv.change_percent) : ''}`.trim();
  }

  function windowText(iv) {
    if (iv.start_index === null || iv.start_index === undefined) return '\u2014';
    const from = iv.start_time_ms ? ` (from ${utc(iv.start_time_ms)})` : '';
    return `snapshots ${iv.start_index}\u2013${iv.end_index}${from}`;
  }

  function predictedText(o) {
    if (!o || !finite(o.predicted_percent)) return '\u2014';
    const conf = finite(o.confidence) ? `${Math.round(100 * o.confidence)} % ` : '';
    return `${signed(o.predicted_percent)} (${conf}${signed(o.predicted_percent_low)} to ${signed(o.predicted_percent_high)})`;
  }

  function resultText(o) {
    if (!o) return 'window not checked yet';
    if (o.status !== 'checked') return o.status.replace(/_/g, ' ');
    return `${o.inside ? 'inside' : 'outside'} the interval \u00b7 ${o.improved ? 'improved' : 'not improved'}`;
  }

  function trustText(o) {
    if (!o || !finite(o.lever_trust)) return '\u2014';
    return `${o.lever_trust.toFixed(2)} (${o.lever_claimed ? 'lever claimed' : 'lever withdrawn'})`;
  }

  function row(iv) {
    const o = iv.outcome;
    const tr = node('tr', { 'data-request-id': iv.request_id, 'data-status': o ? o.status : 'pending' });
    const who = iv.approved_by ? `${iv.approved_by}${iv.approved_time_ms ? ', ' + utc(iv.approved_time_ms) : ''}` : '\u2014';
    tr.appendChild(node('td', { class: 'approved', title: iv.request_id }, who));
    tr.appendChild(node('td', { class: 'lever' }, leverText(iv)));
    tr.appendChild(node('td', { class: 'window' }, windowText(iv)));
    tr.appendChild(node('td', { class: 'target' }, named(iv.target_name, iv.target_channel)));
    tr.appendChild(node('td', { class: 'predicted' }, predictedText(o)));
    tr.appendChild(node('td', { class: 'observed' }, o ? signed(o.observed_percent) : '\u2014'));
    tr.appendChild(node('td', { class: 'result', title: o ? o.text : '' }, resultText(o)));
    tr.appendChild(node('td', { class: 'trust' }, trustText(o)));
    return tr;
  }

  function render(g) {
    const list = g.interventions || [];
    const body = document.querySelector('#interventions tbody');
    if (!body) return;
    const rows = list.slice().reverse().map(row);  // newest first
    if (rows.length === 0) {
      const tr = node('tr');
      tr.appendChild(node('td', { colspan: 8, class: 'muted' }, 'No intervention approved for this group.'));
      rows.push(tr);
    }
    body.replaceChildren(...rows);
    const count = document.getElementById('intervention-count');
    if (count) count.textContent = String(list.length);
  }

  // A recommendation that can be approved: a reliable upstream lever with a channel to change.
  const approvable = (r) => r.action_kind === 'upstream_lever' && r.reliable === true && r.intervene_channel > 0 &&
    finite(r.delta);

  async function approve(r, g, lever) {
    const out = document.getElementById('approve-result');
    const percent = signed(100 * Math.expm1(r.delta));
    if (!window.confirm(`Approve for ${g.id}: change ${lever} by ${percent} (recommendation ${r.id})? ` +
      'The plant applies it for its window.')) return;
    out.dataset.status = 'sending';
    out.dataset.requestId = '';
    out.textContent = `approving ${r.id}\u2026`;
    try {
      const csrf = document.querySelector('meta[name="twin-csrf"]').content;
      const user = (document.getElementById('aa-user') || { value: '' }).value.trim();
      const res = await (await fetch('/api/approve', { method: 'POST',
        headers: { 'Content-Type': 'application/json', 'X-Twin-CSRF': csrf },
        body: JSON.stringify({ asset_group: g.id, recommendation_id: r.id, user }) })).json();
      out.dataset.status = res.published ? 'published' : (res.answered ? 'refused' : 'error');
      out.dataset.requestId = res.request_id || res.already || '';
      out.textContent = res.published
        ? `approved ${res.request_id} by ${res.approved_by}: ${lever} ${signed(res.change_percent)} from snapshot ` +
          `${res.start_snapshot_index} for ${res.duration_snapshots} (${res.readers} readers now; kept for later ones)`
        : `${r.id}: ${res.error || 'failed'}`;
    } catch (e) {
      out.dataset.status = 'error';
      out.textContent = `${r.id}: ${e}`;
    }
  }

  // Under a recommendation: its approve button, or who approved it already; null when it is not approvable.
  function approveBlock(r, g) {
    if (!approvable(r)) return null;
    const done = (g.interventions || []).find((iv) => iv.recommendation_id === r.id);
    const div = node('div', { class: 'approval', 'data-recommendation-id': r.id });
    if (done) {
      div.dataset.approved = 'true';
      div.appendChild(node('span', { class: 'muted', title: done.request_id },
        `approved by ${done.approved_by || '\u2014'}`));
      return div;
    }
    const lever = named(g.channels[r.intervene_channel - 1], r.intervene_channel);
    const b = node('button', { type: 'button', class: 'approve', 'data-recommendation-id': r.id },
      `Approve: ${lever} ${signed(100 * Math.expm1(r.delta))}`);
    b.addEventListener('click', () => approve(r, g, lever));
    div.appendChild(b);
    return div;
  }

  return { render, approveBlock };
})();
