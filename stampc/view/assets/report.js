// stampc view: the report's behaviour. Data comes from #report-data (written by
// stampc/view/page.py); the graph is drawn by vis-network (inlined above) at the
// positions of igraph's tree layout (computed in Python): the browser does no layout.
"use strict";
(function () {
  const DATA = JSON.parse(document.getElementById("report-data").textContent);
  const RAW = DATA.graph;  // compact (stampc/view/model.py): expanded here
  const FACTS = RAW.facts, EFFECTS = RAW.effects;
  const rawById = new Map(RAW.nodes.map(r => [r.id, r]));
  const LEAF_LABEL = {"goal": "goal", "dead-end-proven": "dead end", "dead-end": "dead end?", "horizon": "horizon"};
  const G = {root: RAW.root, nodes: RAW.nodes.map(r => ({
    id: r.id, depth: r.d, status: r.s, x: r.x, y: r.y,
    action: r.a === undefined ? null : RAW.actions[r.a][0],
    label: r.a === undefined ? (LEAF_LABEL[r.s] || r.s) : RAW.actions[r.a][1],
    learned: (r.l || []).map(([fact, value]) => ({fact, value})),
    values: r.v || {},
    outcomes: (r.o || []).map(([p, child, name, adds, dels]) => ({p, child, name, adds: EFFECTS[adds], deletes: EFFECTS[dels]})),
    goal: r.g === undefined ? undefined : EFFECTS[r.g],
  }))};
  const byId = new Map(G.nodes.map(n => [n.id, n]));
  // a state is stored as its difference from its tree parent's: rebuilt on demand
  const stateCache = new Map();
  function stateOf(id) {
    const chain = [];
    let r = rawById.get(id);
    while (!stateCache.has(r.id) && r.st === undefined) { chain.push(r); r = rawById.get(r.sb); }
    let state = stateCache.has(r.id) ? stateCache.get(r.id) : r.st;
    stateCache.set(r.id, state);
    for (let i = chain.length - 1; i >= 0; i--) {
      const del = new Set(chain[i].sd);
      state = state.filter(f => !del.has(f)).concat(chain[i].sa).sort((a, b) => a - b);
      stateCache.set(chain[i].id, state);
    }
    return state;
  }
  const COLORS = {
    "goal": "#3a9d5d", "refined": "#7fb3e6", "unrefined": "#c8cdd2",
    "dead-end-proven": "#c0392b", "dead-end": "#e59866", "horizon": "#f4d03f",
  };
  const STATUS_TEXT = {
    "goal": "goal", "refined": "refined", "unrefined": "unrefined",
    "dead-end-proven": "proven dead end", "dead-end": "dead end (not proven)",
    "horizon": "horizon leaf (unrefined)",
  };
  const big = G.nodes.length > 800;

  function el(tag, attrs, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k === "class") e.className = v; else if (k === "style") e.style.cssText = v;
      else if (k.startsWith("on")) e.addEventListener(k.slice(2), v); else e.setAttribute(k, v);
    }
    for (const c of children) {
      if (c === null || c === undefined) continue;
      e.append(c instanceof Node ? c : document.createTextNode(String(c)));
    }
    return e;
  }
  const fmt = (x, d = 4) => (typeof x === "number" ? (Number.isInteger(x) ? String(x) : x.toFixed(d)) : String(x));
  const badge = s => el("span", {class: "badge", style: `background:${COLORS[s] || "#888"}`}, STATUS_TEXT[s] || s);
  const nodeLink = id => el("a", {class: "node-link", "data-node": id, onclick: () => select(id, true)}, `node ${id}`);

  // ---------------------------------------------------------------- header
  document.getElementById("title").textContent = `${DATA.title}  (${DATA.world} world, seed ${DATA.seed})`;
  const cards = document.getElementById("summary");
  for (const [k, v] of Object.entries(DATA.summary)) {
    cards.append(el("div", {class: "card"}, el("b", {}, fmt(v)), k.replace(/_/g, " ")));
  }
  for (const n of DATA.notes) document.getElementById("notes").append(el("div", {class: "note"}, n));

  // ---------------------------------------------------------------- graph
  const visNodes = G.nodes.map(n => ({
    id: n.id, x: n.x, y: n.y, label: n.label,
    title: `node ${n.id}: ${n.action || n.label} (${STATUS_TEXT[n.status] || n.status})`,
    color: {background: COLORS[n.status] || "#888", border: n.id === G.root ? "#000" : "#555"},
    shape: n.action ? "box" : "ellipse", borderWidth: n.id === G.root ? 3 : 1,
  }));
  const visEdges = [];
  for (const n of G.nodes) {
    n.outcomes.forEach((o, i) => {
      if (!byId.has(o.child)) return;
      const p = fmt(o.p, 3);
      visEdges.push({id: `${n.id}-${i}`, from: n.id, to: o.child, title: `${o.name || "outcome"} p=${p}`,
                     label: big ? undefined : p, width: 0.5 + 3 * o.p});
    });
  }
  performance.mark("stampc:data");
  const container = document.getElementById("graph");
  const network = new vis.Network(container, {nodes: new vis.DataSet(visNodes), edges: new vis.DataSet(visEdges)}, {
    physics: false,
    layout: {improvedLayout: false, hierarchical: false},  // positions from igraph
    interaction: {hover: !big, hideEdgesOnDrag: big, hideEdgesOnZoom: big, tooltipDelay: 150},
    nodes: {font: {size: 14}, margin: 6, scaling: {label: {drawThreshold: 6}}},
    edges: {arrows: {to: {enabled: true, scaleFactor: 0.5}}, smooth: false, color: {color: "#8896a5"},
            font: {size: 11, align: "middle"}},
  });
  performance.mark("stampc:network");
  network.once("afterDrawing", () => {
    // thousands of nodes fit as a thin line: start at the root, "fit" shows everything
    if (big) network.focus(G.root, {scale: 0.7, animation: false});
    document.body.dataset.graphDrawn = "true";
  });
  document.getElementById("node-count").textContent = `(${G.nodes.length} nodes, ${visEdges.length} edges)`;
  const legend = document.getElementById("legend");
  for (const [s, c] of Object.entries(COLORS)) {
    legend.append(el("span", {class: "swatch", style: `background:${c}`}), STATUS_TEXT[s]);
  }
  network.on("click", params => { if (params.nodes.length) select(params.nodes[0], false); });
  document.getElementById("fit").addEventListener("click", () => network.fit());

  // ---------------------------------------------------------------- detail panel
  const revisionsAt = new Map();
  for (const r of (DATA.history && DATA.history.revisions) || []) {
    if (!revisionsAt.has(r.node)) revisionsAt.set(r.node, []);
    revisionsAt.get(r.node).push(r);
  }
  function factList(ids, empty) {
    if (!ids.length) return el("p", {class: "muted"}, empty);
    return el("ul", {class: "mono"}, ...ids.map(i => el("li", {}, FACTS[i])));
  }
  function select(id, focus) {
    const n = byId.get(id);
    if (!n) return;
    network.selectNodes([id]);
    if (focus) network.focus(id, {scale: 1.0, animation: false});
    const d = document.getElementById("detail");
    d.replaceChildren();
    d.dataset.node = id;
    d.append(el("h3", {}, `node ${id} `, badge(n.status)),
             el("p", {}, el("b", {}, n.action || n.label), el("br"), `depth ${n.depth}`));
    let outcomes = [];
    if (n.outcomes.length) {
      const effects = o => [...o.adds.map(i => "+" + FACTS[i]), ...o.deletes.map(i => "−" + FACTS[i])];
      const rows = n.outcomes.map(o => el("tr", {}, el("td", {}, fmt(o.p)), el("td", {}, o.name || "—"),
        el("td", {}, byId.has(o.child) ? nodeLink(o.child) : `node ${o.child}`),
        el("td", {class: "mono"}, el("details", {}, el("summary", {}, `${effects(o).length} effects`), effects(o).join(" ")))));
      outcomes = [el("h4", {}, "Outcomes"), el("table", {class: "outcomes"},
        el("tr", {}, el("th", {}, "p"), el("th", {}, "name"), el("th", {}, "child"), el("th", {}, "effects")), ...rows)];
    }
    const values = Object.entries(n.values);
    d.append(el("h4", {}, "Concrete values"), values.length
      ? el("table", {class: "values"}, ...values.map(([k, v]) => el("tr", {}, el("td", {class: "mono"}, k), el("td", {class: "mono"}, v))))
      : el("p", {class: "muted"}, !n.action ? "a leaf: no action" : n.status === "refined"
          ? "none: the action generates no values" : "none chosen: the action is not refined"));
    d.append(el("h4", {}, "Learned facts"), n.learned.length
      ? el("ul", {class: "mono"}, ...n.learned.map(f => el("li", {}, `${f.fact} = ${f.value}`)))
      : el("p", {class: "muted"}, "none"));
    d.append(...outcomes);
    const revs = revisionsAt.get(id) || [];
    if (revs.length) {
      d.append(el("h4", {}, "PRG revisions here"),
               el("ul", {}, ...revs.map(r => el("li", {}, `#${r.to} ${r.kind}${r.failed ? " (failed)" : ""}: ${r.facts.join(", ") || "—"}`))));
    }
    if (n.goal) d.append(el("h4", {}, "Goal facts"), factList(n.goal, "none"));
    const state = stateOf(id);
    d.append(el("h4", {}, `Abstract state (${state.length} facts)`), factList(state, "empty"));
  }

  // ---------------------------------------------------------------- search
  document.getElementById("search").addEventListener("change", e => {
    const q = e.target.value.trim().toLowerCase();
    if (!q) return;
    const hits = G.nodes.filter(n => String(n.id) === q || (n.action || n.label).toLowerCase().includes(q)
      || stateOf(n.id).some(i => FACTS[i].toLowerCase().includes(q)));
    network.selectNodes(hits.map(n => n.id));
    if (hits.length) select(hits[0].id, true);
  });

  // ---------------------------------------------------------------- PRG history
  (function history() {
    const body = document.getElementById("history-body");
    const h = DATA.history;
    if (!h) { body.append(el("p", {class: "muted"}, "no prg.json in the run directory (written by stampc refine since this report exists)")); return; }
    body.append(el("p", {}, `${h.nodes.length} PRG nodes, ${h.revisions.length} revisions; the reported policy is PRG node ${h.best}.`));
    if (h.revisions.length) {
      const what = r => r.facts.length ? r.facts.join(", ")
        : r.kind === "resample" ? `new generator values (node ${r.failed_node} below found no refinement)`
        : r.kind === "replan" ? "replanned here without the actions banned in every state"
        : "no facts: the action was banned there";
      const rows = h.revisions.map(r => el("tr", {"data-prg": r.to, style: r.to === h.best ? "font-weight:bold" : ""},
        el("td", {}, `#${r.to}`), el("td", {}, `#${r.from}`),
        el("td", {}, fmt(r.time_s, 3)), el("td", {}, r.kind + (r.failed ? " (failed: no way to the goal below)" : "")),
        el("td", {}, byId.has(r.node) ? nodeLink(r.node) : `node ${r.node} (not in the final policy)`),
        el("td", {class: "mono"}, what(r))));
      body.append(el("div", {class: "scroll"}, el("table", {id: "revisions"},
        el("tr", {}, ...["PRG node", "from", "time (s)", "kind", "at", "learned or changed"].map(t => el("th", {}, t))), ...rows)));
    }
    const events = h.events.map(e => el("tr", {}, el("td", {}, fmt(e.time_s, 3)), el("td", {}, e.kind),
      el("td", {}, fmt(e.coverage, 3)), el("td", {}, e.prg_nodes), el("td", {class: "mono"}, e.detail || "")));
    body.append(el("details", {}, el("summary", {}, `all ${h.events.length} engine events`),
      el("table", {}, el("tr", {}, ...["time (s)", "kind", "coverage", "PRG nodes", "detail"].map(t => el("th", {}, t))), ...events)));
  })();

  // ---------------------------------------------------------------- frames
  (function frames() {
    const body = document.getElementById("frames-body");
    if (!DATA.frames.length) {
      body.append(el("p", {class: "muted"}, "no frames in the run directory: `stampc execute RUN/policy.json --render RUN/frames` records the first run's branch"));
      return;
    }
    const img = el("img", {id: "frame-img", src: DATA.frames[0], alt: "frame"});
    const label = el("span", {}, `1 / ${DATA.frames.length}`);
    const slider = el("input", {type: "range", min: 0, max: DATA.frames.length - 1, value: 0});
    const show = i => { img.src = DATA.frames[i]; slider.value = i; label.textContent = `${+i + 1} / ${DATA.frames.length}`; };
    slider.addEventListener("input", () => show(slider.value));
    let timer = null;
    const play = el("button", {onclick: () => {
      if (timer) { clearInterval(timer); timer = null; play.textContent = "play"; return; }
      play.textContent = "pause";
      timer = setInterval(() => show((+slider.value + 1) % DATA.frames.length), 150);
    }}, "play");
    body.append(el("p", {}, `The branch taken by the first run of \`stampc execute --render\` (${DATA.frames_dir}/), ${DATA.frames.length} frames.`),
                img, el("div", {class: "toolbar"}, play, slider, label));
  })();

  // ---------------------------------------------------------------- execution
  (function execution() {
    const body = document.getElementById("execution-body");
    if (!DATA.executions.length) {
      body.append(el("p", {class: "muted"}, "no execute*.json in the run directory: `stampc execute RUN/policy.json --format json > RUN/execute.json` adds them"));
      return;
    }
    for (const x of DATA.executions) {
      const ci = x.success_ci95 || [];
      body.append(el("h3", {}, x.file), el("p", {},
        `${x.runs} runs: ${x.success} successes (${fmt(x.success_rate, 3)}, 95% CI [${ci.map(v => fmt(v, 3)).join(", ")}]), `
        + `predicted ${fmt(x.predicted_success, 3)}; failures ${x.failure}, dead ends ${x.dead_end}, unrefined ${x.unrefined}, `
        + `collisions ${x.collisions}, goal-check failures ${x.goal_check_failures}`));
      const rows = [];
      for (const [action, row] of Object.entries(x.outcomes || {})) {
        for (const [name, c] of Object.entries(row)) {
          rows.push(el("tr", {}, el("td", {}, action), el("td", {}, name), el("td", {}, c.executions),
            el("td", {}, fmt(c.observed, 3)), el("td", {}, fmt(c.model, 3)), el("td", {}, fmt(c.truth, 3))));
        }
      }
      if (rows.length) body.append(el("table", {class: "exec"}, el("tr", {}, ...["action", "outcome", "executions", "observed", "model", "truth"].map(t => el("th", {}, t))), ...rows));
    }
  })();

  // ---------------------------------------------------------------- node table
  // built when first opened: thousands of rows would delay every page load
  const tbody = document.querySelector("#node-table tbody");
  tbody.addEventListener("click", e => {
    const row = e.target.closest("tr[data-node]");
    if (!row) return;
    select(Number(row.dataset.node), true);
    document.getElementById("policy").scrollIntoView();
  });
  document.querySelector("#all-nodes details").addEventListener("toggle", () => {
    if (tbody.childElementCount) return;
    const frag = document.createDocumentFragment();
    for (const n of G.nodes) {
      frag.append(el("tr", {"data-node": n.id}, el("td", {}, n.id), el("td", {}, n.depth),
        el("td", {}, STATUS_TEXT[n.status] || n.status), el("td", {}, n.action || n.label)));
    }
    tbody.append(frag);
  });

  const stateFacts = id => stateOf(id).map(i => FACTS[i]);
  window.stampcReport = {network, select, stateFacts, nodeCount: G.nodes.length, edgeCount: visEdges.length};
  document.body.dataset.ready = "true";
})();
