// The page's entry: the workbench shell (app/shell.js) with its tools, one module each.
// A new tool is a module in tools/ (its panel, results and viewer layers) plus, when it needs
// the engine, a module in worker/ registered in worker/worker.js; see the interface in
// app/shell.js.
import { shell } from './app/shell.js';
import { segmentTool } from './tools/segment.js';
import { sprayTool } from './tools/spray.js';
import { drillTool } from './tools/drill.js';
import { pathsTool } from './tools/paths.js';

shell.addTool(segmentTool);
shell.addTool(sprayTool);
shell.addTool(drillTool);
shell.addTool(pathsTool);
shell.start();
