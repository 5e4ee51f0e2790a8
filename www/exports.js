// Files the page offers for download: the patch table as CSV and JSON, and the helpers that
// hand bytes to the browser. The STL and zip bytes themselves come from the worker.

/** File-name stem of a model: "wing v2.stl" -> "wing_v2". */
export function fileStem(name) {
  const stem = name.replace(/\.[^.]*$/, '').replace(/[^\w.-]+/g, '_').replace(/^_+|_+$/g, '');
  return stem || 'model';
}

/** Everything that describes one segmentation, as one plain object (the JSON export). */
export function patchTable({ model, segmentation, params, units }) {
  return {
    generator: 'skinpath',
    created: new Date().toISOString(),
    model: {
      name: model.name,
      format: model.report.format,
      triangles: model.report.triangles,
      vertices: model.report.vertices,
      area: model.report.area,
      bboxMin: model.report.bboxMin,
      bboxMax: model.report.bboxMax,
    },
    // STL has no units: "length" is the unit the user said the file's numbers are in.
    units: { length: units.length, area: `${units.length}^2`, angle: 'rad', curvature: `1/${units.length}` },
    parameters: params,
    threshold: { kind: segmentation.thresholdKind, value: segmentation.threshold },
    patchCount: segmentation.patchCount,
    patches: segmentation.patches.map((p) => ({
      id: p.id,
      triangleCount: p.triangleCount,
      area: p.area,
      normal: p.normal,
      maxDeviation: p.maxDeviation,
      centroid: p.centroid,
    })),
  };
}

export function tableToJson(table) {
  return JSON.stringify(table, null, 2) + '\n';
}

/** CSV with the parameters as leading '#' comment lines (pandas: comment='#'). */
export function tableToCsv(table) {
  const u = table.units.length;
  const lines = [
    `# skinpath patch table for ${table.model.name}`,
    `# units: length ${u}, area ${u}^2, angles rad`,
    `# parameters: ${JSON.stringify(table.parameters)}`,
    `# growing threshold: ${table.threshold.kind} ${table.threshold.value}`,
    ['patch_id', 'triangles', `area_${u}2`, 'normal_x', 'normal_y', 'normal_z', 'max_deviation_rad',
      `centroid_x_${u}`, `centroid_y_${u}`, `centroid_z_${u}`].join(','),
  ];
  for (const p of table.patches) {
    lines.push([p.id, p.triangleCount, p.area, ...p.normal, p.maxDeviation, ...p.centroid].join(','));
  }
  return lines.join('\r\n') + '\r\n';
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
