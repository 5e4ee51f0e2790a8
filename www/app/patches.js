// The patch list (right panel): one row per kept patch, sortable, with show/hide/isolate.
// It is the shell's, because every tool selects patches through it (and in the view).
import { patchColor } from '../viewer/viewer.js';
import { integer, num } from './format.js';

/** Rows drawn in the patch table; the rest are summarised (the exports hold them all). */
const MAX_TABLE_ROWS = 2000;

const $ = (id) => document.getElementById(id);

const EYE = '<svg aria-hidden="true" viewBox="0 0 16 16" width="14" height="14"><path d="M1 8s2.5-4.5 7-4.5S15 8 15 8s-2.5 4.5-7 4.5S1 8 1 8z" fill="none" stroke="currentColor" stroke-width="1.3"/><circle cx="8" cy="8" r="2" fill="currentColor"/></svg>';
const TARGET = '<svg aria-hidden="true" viewBox="0 0 16 16" width="14" height="14"><circle cx="8" cy="8" r="5.5" fill="none" stroke="currentColor" stroke-width="1.3"/><circle cx="8" cy="8" r="1.8" fill="currentColor"/></svg>';

export class PatchList {
  #shell;
  #sort = { key: 'id', descending: false };

  constructor(shell) {
    this.#shell = shell;
    this.#wire();
  }

  #sorted() {
    const { key, descending } = this.#sort;
    const patches = [...(this.#shell.state.segmentation?.patches ?? [])];
    patches.sort((a, b) => (a[key] - b[key]) * (descending ? -1 : 1) || a.id - b.id);
    return patches;
  }

  render() {
    const { state } = this.#shell;
    const body = $('patch-rows');
    const patches = this.#sorted();
    const rows = patches.slice(0, MAX_TABLE_ROWS).map((p) => {
      const tr = document.createElement('tr');
      tr.dataset.patchId = String(p.id);
      tr.tabIndex = -1;
      tr.setAttribute('aria-selected', String(p.id === state.selected));
      tr.classList.toggle('is-hidden', state.hidden.has(p.id));
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.backgroundColor = patchColor(p.id);
      const idCell = document.createElement('td');
      idCell.append(swatch, `${p.id}`);
      const cell = (text, className) => Object.assign(document.createElement('td'), { textContent: text, className: className ?? '' });
      const actions = document.createElement('td');
      const hidden = state.hidden.has(p.id);
      actions.innerHTML = '<span class="row-actions">' +
        `<button type="button" data-action="toggle" aria-pressed="${!hidden}" aria-label="${hidden ? 'Show' : 'Hide'} patch ${p.id}" title="${hidden ? 'Show' : 'Hide'} (H)">${EYE}</button>` +
        `<button type="button" data-action="isolate" aria-label="Show only patch ${p.id}" title="Isolate (I)">${TARGET}</button></span>`;
      tr.append(
        idCell,
        cell(integer.format(p.triangleCount)),
        cell(num(p.area)),
        cell(p.normal.map((c) => (Math.abs(c) < 0.005 ? 0 : c).toFixed(2)).join(',\u2009'), 'normal'),
        cell(state.settings.angleUnit === 'deg' ? ((p.maxDeviation * 180) / Math.PI).toFixed(1) : p.maxDeviation.toFixed(3)),
        actions,
      );
      return tr;
    });
    body.replaceChildren(...rows);
    const focusRow = body.querySelector('tr[aria-selected="true"]') ?? body.firstElementChild;
    if (focusRow) focusRow.tabIndex = 0;
    const note = $('patch-table-note');
    note.hidden = patches.length <= MAX_TABLE_ROWS;
    note.textContent = `Showing the first ${integer.format(MAX_TABLE_ROWS)} of ${integer.format(patches.length)} patches in this order; the exports contain all of them.`;
    for (const th of document.querySelectorAll('#patch-table th')) {
      const key = th.querySelector('button[data-sort]')?.dataset.sort;
      if (!key) continue;
      if (key === this.#sort.key) th.setAttribute('aria-sort', this.#sort.descending ? 'descending' : 'ascending');
      else th.removeAttribute('aria-sort');
    }
    this.#renderSummary();
  }

  #renderSummary() {
    const { state } = this.#shell;
    const seg = state.segmentation;
    const summary = $('patch-summary');
    if (!state.model) return;
    if (!seg) {
      summary.textContent = 'Not segmented: check the segmentation settings on the left.';
      return;
    }
    const covered = seg.patches.reduce((sum, p) => sum + p.area, 0);
    const keptTriangles = seg.patches.reduce((sum, p) => sum + p.triangleCount, 0);
    const dropped = state.model.report.triangles - keptTriangles;
    const share = state.model.report.area > 0 ? (100 * covered) / state.model.report.area : 100;
    if (seg.patchCount === 0) {
      summary.textContent = `No patch reaches the minimum area (${num(100 * (state.settings.minAreaRatio ?? 0), 3)} % of the surface): ` +
        'lower the minimum patch area, or loosen the growing threshold so regions can grow.';
      return;
    }
    summary.textContent = `${seg.patchCount} ${seg.patchCount === 1 ? 'patch covers' : 'patches cover'} ${num(share, 3)} % of the surface` +
      (dropped > 0 ? `; ${integer.format(dropped)} triangles in small regions are dropped (grey).` : '.');
  }

  #row(id) {
    return $('patch-rows').querySelector(`tr[data-patch-id="${id}"]`);
  }

  markSelected(id, { scroll = true, focus = false } = {}) {
    for (const tr of $('patch-rows').querySelectorAll('tr[aria-selected="true"]')) {
      tr.setAttribute('aria-selected', 'false');
      tr.tabIndex = -1;
    }
    const row = id === null ? null : this.#row(id);
    if (row) {
      row.setAttribute('aria-selected', 'true');
      row.tabIndex = 0;
      if (scroll) row.scrollIntoView({ block: 'nearest' });
      if (focus) row.focus();
    } else {
      const first = $('patch-rows').firstElementChild;
      if (first) first.tabIndex = 0;
    }
  }

  markHidden(hidden) {
    for (const tr of $('patch-rows').children) {
      const id = Number(tr.dataset.patchId);
      const isHidden = hidden.has(id);
      tr.classList.toggle('is-hidden', isHidden);
      const button = tr.querySelector('[data-action="toggle"]');
      button.setAttribute('aria-pressed', String(!isHidden));
      button.setAttribute('aria-label', `${isHidden ? 'Show' : 'Hide'} patch ${id}`);
      button.title = `${isHidden ? 'Show' : 'Hide'} (H)`;
    }
  }

  #wire() {
    const shell = this.#shell;
    for (const button of document.querySelectorAll('#patch-table th button[data-sort]')) {
      button.addEventListener('click', () => {
        const key = button.dataset.sort;
        this.#sort = { key, descending: this.#sort.key === key ? !this.#sort.descending : key !== 'id' };
        this.render();
      });
    }
    const rows = $('patch-rows');
    rows.addEventListener('click', (event) => {
      const tr = event.target.closest('tr[data-patch-id]');
      if (!tr) return;
      const id = Number(tr.dataset.patchId);
      const action = event.target.closest('button[data-action]')?.dataset.action;
      if (action === 'toggle') shell.toggleHidden(id);
      else if (action === 'isolate') shell.isolate(id);
      else shell.select(id, { scroll: false, focus: true });
    });
    rows.addEventListener('dblclick', (event) => {
      const tr = event.target.closest('tr[data-patch-id]');
      if (tr && !event.target.closest('button')) shell.viewer.fitPatch(Number(tr.dataset.patchId));
    });
    rows.addEventListener('keydown', (event) => {
      const tr = event.target.closest('tr[data-patch-id]');
      if (!tr || event.target !== tr) return;
      let next = null;
      if (event.key === 'ArrowDown') next = tr.nextElementSibling;
      else if (event.key === 'ArrowUp') next = tr.previousElementSibling;
      else if (event.key === 'Home') next = rows.firstElementChild;
      else if (event.key === 'End') next = rows.lastElementChild;
      else if (event.key === 'Enter' || event.key === ' ') next = tr;
      if (!next) return;
      event.preventDefault();
      shell.select(Number(next.dataset.patchId), { focus: true });
    });
    $('show-all-button').addEventListener('click', () => shell.setHidden(new Set()));
    $('show-borders').addEventListener('change', () => shell.syncViewer());
    $('show-dropped').addEventListener('change', (event) => {
      const hidden = new Set(shell.state.hidden);
      if (event.target.checked) hidden.delete(-1);
      else hidden.add(-1);
      shell.setHidden(hidden);
    });
  }
}
