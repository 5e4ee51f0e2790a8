// Handing files to the browser as downloads. The bytes come from the tools (and their
// worker modules).

/** File-name stem of a model: "wing v2.stl" -> "wing_v2". */
export function fileStem(name) {
  const stem = name.replace(/\.[^.]*$/, '').replace(/[^\w.-]+/g, '_').replace(/^_+|_+$/g, '');
  return stem || 'model';
}

/** Starts a download of `data` (string, Uint8Array or Blob) under `fileName`. */
export function download(data, fileName, type = 'application/octet-stream') {
  const blob = data instanceof Blob ? data : new Blob([data], { type });
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = fileName;
  a.hidden = true;
  document.body.append(a);
  a.click();
  a.remove();
  // The download has started by the time the click returns; revoke a little later for Safari.
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}
