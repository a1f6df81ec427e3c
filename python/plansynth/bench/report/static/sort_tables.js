// Sortable tables: a click (or Enter) on a column's header sorts the table's rows by that
// column, again to reverse. Numbers sort as numbers ("> 60" just above 60), names in
// natural order (steps-5 before steps-10), and a cell without a number after those with one.
"use strict";
(function () {
  const NUMBER = /^\s*([<>]?)\s*(-?\d+(?:\.\d+)?(?:e[-+]?\d+)?)/i;
  function key(cell) {
    const text = cell.textContent.trim();
    const m = NUMBER.exec(text);
    if (!m) return { rank: 1, text: text };
    const v = parseFloat(m[2]);
    const bound = m[1] === ">" ? 1 : m[1] === "<" ? -1 : 0;
    return { rank: 0, value: v, bound: bound, text: text };
  }
  function compare(a, b) {
    if (a.rank !== b.rank) return a.rank - b.rank;
    if (a.rank === 0 && a.value !== b.value) return a.value - b.value;
    if (a.rank === 0 && a.bound !== b.bound) return a.bound - b.bound;
    return a.text.localeCompare(b.text, undefined, { numeric: true });
  }
  function sortBy(table, th, column) {
    const body = table.tBodies[0];
    const order = th.getAttribute("aria-sort") === "ascending" ? -1 : 1;
    const rows = Array.from(body.rows).map((row, i) => ({ row: row, i: i, key: key(row.cells[column] || row) }));
    rows.sort((a, b) => order * compare(a.key, b.key) || a.i - b.i);
    rows.forEach((r) => body.appendChild(r.row));
    table.querySelectorAll("thead th").forEach((h) => h.removeAttribute("aria-sort"));
    th.setAttribute("aria-sort", order === 1 ? "ascending" : "descending");
  }
  document.querySelectorAll("main table").forEach((table) => {
    if (!table.tHead || !table.tBodies.length || table.tBodies[0].rows.length < 2) return;
    Array.from(table.tHead.rows[0].cells).forEach((th, column) => {
      th.classList.add("sortable");
      th.tabIndex = 0;
      th.title = "sort by this column";
      th.addEventListener("click", () => sortBy(table, th, column));
      th.addEventListener("keydown", (e) => { if (e.key === "Enter") sortBy(table, th, column); });
    });
  });
  document.body.dataset.ready = "report";
})();
