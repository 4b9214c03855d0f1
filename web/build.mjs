// Builds the console, the admin and settings pages, the face kiosk page and the API page into web/dist: one bundled script each, the
// pages, the styles (ours and Leaflet's), and Swagger UI's prebuilt bundle for the API page.
import { build } from 'esbuild';
import { cpSync, mkdirSync } from 'node:fs';

const dist = new URL('./dist/', import.meta.url).pathname;
mkdirSync(dist, { recursive: true });
await build({
  entryPoints: ['src/main.ts'],
  bundle: true,
  minify: true,
  sourcemap: true,
  target: 'es2022',
  outfile: `${dist}app.js`,
  logLevel: 'warning',
});
await build({
  entryPoints: ['src/face/main.ts'],
  bundle: true,
  minify: true,
  sourcemap: true,
  target: 'es2022',
  format: 'esm',
  outfile: `${dist}face.js`,
  logLevel: 'warning',
});
await build({
  entryPoints: ['src/settings.ts'],
  bundle: true,
  minify: true,
  sourcemap: true,
  target: 'es2022',
  format: 'esm',
  outfile: `${dist}settings.js`,
  logLevel: 'warning',
});
await build({
  entryPoints: ['src/admin.ts'],
  bundle: true,
  minify: true,
  sourcemap: true,
  target: 'es2022',
  format: 'esm',
  outfile: `${dist}admin.js`,
  logLevel: 'warning',
});
await build({
  entryPoints: ['src/api_docs.ts'],
  bundle: true,
  minify: true,
  target: 'es2022',
  outfile: `${dist}api-docs.js`,
  logLevel: 'warning',
});
cpSync('index.html', `${dist}index.html`);
cpSync('api-docs.html', `${dist}api-docs.html`);
cpSync('node_modules/swagger-ui-dist/swagger-ui-bundle.js', `${dist}swagger-ui-bundle.js`);
cpSync('node_modules/swagger-ui-dist/swagger-ui.css', `${dist}swagger-ui.css`);
cpSync('node_modules/uplot/dist/uPlot.min.css', `${dist}uPlot.min.css`);
cpSync('admin.html', `${dist}admin.html`);
cpSync('settings.html', `${dist}settings.html`);
cpSync('face.html', `${dist}face.html`);
cpSync('style.css', `${dist}style.css`);
cpSync('favicon.svg', `${dist}favicon.svg`);
cpSync('node_modules/leaflet/dist/leaflet.css', `${dist}leaflet.css`);
cpSync('node_modules/@geoman-io/leaflet-geoman-free/dist/leaflet-geoman.css', `${dist}leaflet-geoman.css`);
