// Bundles src/main.ts (and the CSS it imports, uPlot's included) into dist/assets with
// content hashes in the names, and writes dist/index.html naming them. CMake embeds dist/
// into the rangekit binary (cmake/embed_assets.cmake); nothing is fetched from elsewhere.
import * as esbuild from 'esbuild';
import { mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import path from 'node:path';

const dist = 'dist';
rmSync(dist, { recursive: true, force: true });
mkdirSync(dist, { recursive: true });
const result = await esbuild.build({
  entryPoints: { app: 'src/main.ts' },
  bundle: true,
  minify: true,
  format: 'esm',
  target: ['es2020', 'chrome100', 'firefox100', 'safari15'],
  outdir: path.join(dist, 'assets'),
  entryNames: '[name]-[hash]',
  metafile: true,
  logLevel: 'warning',
  legalComments: 'none',
});
const outputs = Object.keys(result.metafile.outputs).map((file) => path.relative(dist, file));
const script = outputs.find((file) => file.endsWith('.js'));
const style = outputs.find((file) => file.endsWith('.css'));
if (!script || !style) throw new Error(`esbuild made no script or style: ${outputs.join(', ')}`);
const page = readFileSync('index.html', 'utf8')
  .replace('<!-- style -->', `<link rel="stylesheet" href="/${style}">`)
  .replace('<!-- script -->', `<script type="module" src="/${script}"></script>`);
writeFileSync(path.join(dist, 'index.html'), page);
console.log(`dashboard: ${outputs.join(', ')}, index.html`);
