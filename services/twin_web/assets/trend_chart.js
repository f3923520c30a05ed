// The condition trends of one asset group (Chart.js): one line per channel over UTC time, alarm bands behind
// them. The x axis is time in ms since the epoch, with ticks on whole UTC hours or days.
'use strict';

window.renderTrendChart = (function () {
  const COLOURS = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#8c564b', '#e377c2'];
  const BAND = { advisory: 'rgba(240,190,30,0.14)', warning: 'rgba(240,130,30,0.16)', critical: 'rgba(215,40,40,0.18)' };
  const HOUR = 3600e3, DAY = 24 * HOUR;
  const STEPS = [HOUR / 6, HOUR / 2, HOUR, 2 * HOUR, 3 * HOUR, 6 * HOUR, 12 * HOUR, DAY, 2 * DAY, 7 * DAY, 14 * DAY, 28 * DAY];
  let chart = null;

  // Ticks on round UTC times, at most ~9 of them.
  function utcTicks(min, max) {
    const step = STEPS.find((s) => (max - min) / s <= 9) || STEPS[STEPS.length - 1];
    const ticks = [];
    for (let t = Math.ceil(min / step) * step; t <= max; t += step) ticks.push({ value: t });
    return { ticks, step };
  }
  function tickLabel(v, step) {
    const s = new Date(v).toISOString();
    return step >= DAY ? s.slice(0, 10) : s.slice(5, 16).replace('T', ' ');
  }

  function logTick(v) {
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

  function options(g, positive) {
    return {
      animation: false, parsing: false, normalized: true, maintainAspectRatio: false,
      interaction: { mode: 'nearest', axis: 'x', intersect: false },
      scales: {
        x: {
          type: 'linear', title: { display: true, text: 'time (UTC)' },
          afterBuildTicks: (scale) => {
            const t = utcTicks(scale.min, scale.max);
            scale.ticks = t.ticks;
            scale.$utcStep = t.step;
          },
          ticks: { maxRotation: 0, autoSkip: false, callback(v) { return tickLabel(v, this.$utcStep || DAY); } },
        },
        y: {
          type: positive ? 'logarithmic' : 'linear',
          title: { display: true, text: g.feature || 'condition' },
          ticks: { callback(v) { return this.type === 'logarithmic' ? logTick(v) : Number(Number(v).toPrecision(3)).toString(); } },
        },
      },
      plugins: { legend: { position: 'top' }, tooltip: { callbacks: {} } },
    };
  }

  // Draws (or redraws) g's trend on canvas; returns the number of points drawn.
  return function render(canvas, g, noteEl) {
    const t = g.trend;
    const n = t.index.length;
    if (!window.Chart) { noteEl.textContent = 'Chart.js is not installed (Debian package libjs-chart.js).'; return n * g.channels.length; }
    // A gap in the snapshot indices (the twin was down, data was lost) is drawn as a gap: a null point between
    // the two sides, and spanGaps false, so no straight line pretends to know what happened there.
    const points = (c) => {
      const out = [];
      t.time_ms.forEach((x, i) => {
        if (i > 0 && t.index[i] - t.index[i - 1] > 1) out.push({ x: (t.time_ms[i - 1] + x) / 2, y: null });
        out.push({ x, y: t.values[c][i] });
      });
      return out;
    };
    const datasets = g.channels.map((name, c) => ({
      label: name,
      data: points(c),
      borderColor: COLOURS[c % COLOURS.length], backgroundColor: COLOURS[c % COLOURS.length],
      borderWidth: 1.4, pointRadius: 0, tension: 0, spanGaps: false,
    }));
    const positive = t.values.every((v) => v.every((y) => y > 0));
    // A robust lower end (the 1st percentile): a stopped machine's last snapshot must not crush the axis.
    const all = t.values.flat().sort((a, b) => a - b);
    const p1 = all.length ? all[Math.floor(0.01 * all.length)] : undefined;
    const yMin = p1 === undefined ? undefined : (positive ? p1 * 0.8 : p1 - 0.05 * Math.abs(all[all.length - 1] - p1));
    const last = n > 0 ? t.time_ms[n - 1] : 0;
    const bands = g.alarms.filter((a) => a.channel >= 1).map((a) => ({
      from: a.raised_time_ms, to: a.cleared_time_ms !== null ? a.cleared_time_ms : last, severity: a.severity, channel: a.channel,
    }));
    const indexOf = new Map(t.time_ms.map((x, i) => [x, t.index[i]]));
    if (!chart) {
      chart = new window.Chart(canvas, { type: 'line', data: { datasets }, options: options(g, positive), plugins: [bandPlugin] });
    } else {
      chart.data.datasets = datasets;
      chart.options.scales.y.type = positive ? 'logarithmic' : 'linear';
      chart.options.scales.y.title.text = g.feature || 'condition';
    }
    chart.options.scales.x.min = n > 0 ? t.time_ms[0] : undefined;
    chart.options.scales.x.max = n > 0 ? last : undefined;
    chart.options.scales.y.min = yMin;
    chart.options.plugins.tooltip.callbacks.title = (items) => (items.length
      ? `${window.twinFormat.utc(items[0].parsed.x)} \u00b7 snapshot ${indexOf.get(items[0].parsed.x)}` : '');
    chart.$alarmBands = bands;
    chart.update('none');
    return n * g.channels.length;
  };
})();
