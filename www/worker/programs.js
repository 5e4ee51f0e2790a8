// Export files shared by every tool that writes a tool path (spray, paths, drill): the texts
// the engine wrote become one download, a single file as it is or several in one ZIP.
import { strToU8, zipSync } from '../vendor/fflate/esm/browser.js';

/** Robot programs name their module or routine in the text; use it as the file name. */
function fileNameOf(text, format, stem, index) {
  if (format === 'rapid') {
    const m = text.match(/^\s*MODULE\s+(\w+)/m);
    return `${m ? m[1] : `${stem}_${index}`}.mod`;
  }
  const m = text.match(/^\s*DEF\s+(\w+)\s*\(/im);
  return `${m ? m[1] : `${stem}_${index}`}.src`;
}

/**
 * The texts of a tool-path object (a SprayPlan or a ToolPath) in `format`:
 * 'csv' | 'json' (one text) or 'rapid' | 'krl' (one per file).
 */
export function exportTexts(source, format, options) {
  if (format === 'csv') return [source.toCsv(options)];
  if (format === 'json') return [source.toJson(options)];
  if (format === 'rapid') return source.toRapid(options);
  if (format === 'krl') return source.toKrl(options);
  throw new Error(`Unknown export format "${format}".`);
}

/**
 * `texts` in `format` as one download named from `stem` (e.g. "wing_spray"): the op result
 * `[{ fileName, bytes, fileCount }, transfer]` the worker protocol expects.
 */
export function packageFiles(texts, format, stem, progress) {
  const ext = { csv: 'csv', json: 'json' }[format];
  const names = texts.map((text, i) => (ext ? `${stem}.${ext}` : fileNameOf(text, format, stem, i)));
  if (texts.length === 1) {
    const bytes = strToU8(texts[0]);
    return [{ fileName: names[0], bytes, fileCount: 1 }, [bytes.buffer]];
  }
  const files = {};
  texts.forEach((text, i) => {
    let name = names[i];
    for (let k = 2; name in files; k++) name = names[i].replace(/(\.\w+)$/, `_${k}$1`);
    files[name] = strToU8(text);
  });
  progress?.('Compressing', 0.5);
  const bytes = zipSync(files, { level: 6 });
  return [{ fileName: `${stem}_${format}.zip`, bytes, fileCount: texts.length }, [bytes.buffer]];
}
