// Number and unit formatting shared by the shell and the tools.

export const integer = new Intl.NumberFormat('en-US');

/** A measured quantity with `digits` significant figures, thin grouping, no exponent for common sizes. */
export function num(x, digits = 4) {
  if (!Number.isFinite(x)) return '–';
  if (x === 0) return '0';
  const magnitude = Math.abs(x);
  if (magnitude >= 1e-3 && magnitude < 1e7) {
    return new Intl.NumberFormat('en-US', { maximumSignificantDigits: digits }).format(x);
  }
  const [mantissa, exponent] = x.toExponential(digits - 1).split('e');
  return `${mantissa} × 10^${Number(exponent)}`;
}

export function bytesText(bytes) {
  if (bytes >= 1024 ** 3) return `${num(bytes / 1024 ** 3, 3)} GiB`;
  if (bytes >= 1024 ** 2) return `${num(bytes / 1024 ** 2, 3)} MiB`;
  return `${num(bytes / 1024, 3)} KiB`;
}

/** A length given in metres, in the most readable of mm, m and km. */
export function metresText(m) {
  if (m >= 1000) return `${num(m / 1000, 3)} km`;
  if (m >= 1) return `${num(m, 3)} m`;
  if (m >= 1e-3) return `${num(m * 1000, 3)} mm`;
  return `${num(m * 1e6, 3)} µm`;
}

/**
 * A point `(x, y, z)` with `digits` significant figures and no grouping (a grouping comma
 * would read as another coordinate).
 */
export function pointText(p, digits = 6) {
  return `(${p.map((x) => fieldText(x, digits)).join(', ')})`;
}

/** Short text for a form field: no 0.35000000000000003 (and 6 digits are plenty for degrees). */
export function fieldText(x, digits = 10) {
  return String(Number(x.toPrecision(digits)));
}
