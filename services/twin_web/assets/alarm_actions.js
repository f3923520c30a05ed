// Alarm management on the page (ISA-18.2): under each alarm its handling (acknowledged by whom, shelved until when)
// and the buttons to acknowledge, shelve (the form's minutes and reason) or unshelve it; the group's alarm-system
// health (unacknowledged, shelved, alarms per 10 min with the flood mark, standing, chattering). Actions are POSTed
// to /api/alarm_action with the page's CSRF token, like the what-if form. Text is set as text, never HTML.
'use strict';

window.alarmActions = (function () {
  const { node, utc } = window.twinFormat;
  const $ = (id) => document.getElementById(id);

  function handlingText(a) {
    const parts = [];
    parts.push(a.acknowledged ? `acknowledged${a.acknowledged_by ? ' by ' + a.acknowledged_by : ''}` : 'unacknowledged');
    if (a.shelved) {
      let s = 'shelved';
      if (a.shelved_until_ms) s += ` until ${utc(a.shelved_until_ms)}`;
      if (a.shelved_by) s += ` by ${a.shelved_by}`;
      if (a.shelve_reason) s += `: ${a.shelve_reason}`;
      parts.push(s);
    }
    return parts.join(' \u00b7 ');
  }

  async function send(body) {
    const out = $('aa-result');
    out.dataset.status = 'sending';
    out.textContent = `${body.action}: sending\u2026`;
    try {
      const csrf = document.querySelector('meta[name="twin-csrf"]').content;
      const r = await fetch('/api/alarm_action', { method: 'POST',
        headers: { 'Content-Type': 'application/json', 'X-Twin-CSRF': csrf }, body: JSON.stringify(body) });
      const res = await r.json();
      if (res.applied) {
        out.dataset.status = 'applied';
        out.textContent = `${res.action} ${res.alarm_id}: applied`;
      } else {
        out.dataset.status = res.answered ? 'refused' : 'error';
        out.textContent = `${body.action} ${body.alarm_id}: ${res.error || 'failed'}`;
      }
    } catch (e) {
      out.dataset.status = 'error';
      out.textContent = `${body.action}: ${e}`;
    }
  }

  function button(label, cls, body) {
    const b = node('button', { type: 'button', class: `aa ${cls}` }, label);
    b.addEventListener('click', () => {
      const user = $('aa-user').value.trim();
      const full = Object.assign({ user }, body);
      if (body.action === 'shelve') {
        full.minutes = Number($('aa-minutes').value);
        full.reason = $('aa-reason').value.trim();
      }
      send(full);
    });
    return b;
  }

  // The handling line and buttons of one alarm (inside its reason cell).
  function block(a, g) {
    const div = node('div', { class: 'handling', 'data-acknowledged': String(!!a.acknowledged),
      'data-shelved': String(!!a.shelved) });
    div.appendChild(node('span', { class: 'handling-state' }, handlingText(a)));
    const base = { asset_group: g.id, alarm_id: a.id };
    if (a.open && !a.acknowledged) div.appendChild(button('Acknowledge', 'ack', Object.assign({ action: 'acknowledge' }, base)));
    if (a.shelved) {
      div.appendChild(button('Unshelve', 'unshelve', Object.assign({ action: 'unshelve' }, base)));
    } else {
      div.appendChild(button('Shelve', 'shelve', Object.assign({ action: 'shelve' }, base)));
    }
    return div;
  }

  // The group's alarm-system health, from its status line.
  function renderHealth(g) {
    const out = $('alarm-health');
    if (!out) return;
    const s = g.status;
    if (!s || s.unacknowledged_alarms === undefined) {
      out.textContent = '';
      return;
    }
    out.dataset.flood = String(!!s.alarm_flood);
    out.textContent = `Alarm system: ${s.unacknowledged_alarms} unacknowledged, ${s.shelved_alarms} shelved, ` +
      `${s.alarms_per_10_min} raised in the last 10 min${s.alarm_flood ? ' (FLOOD: more than 10)' : ''}, ` +
      `${s.standing_alarms} standing (open > 24 h), ${s.chattering_alarms} chattering (3+ in a minute).`;
  }

  return { block, renderHealth };
})();
