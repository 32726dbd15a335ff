// Vite builds the viewer into web-client/dist, which the server serves at `/`.
// In development (`npm run dev`) /api (REST and the WebSocket) goes to a
// server running on 127.0.0.1:8080, or to $CGVIEW_API.
import { defineConfig } from 'vite';

// Node's `process`, declared here so that tsc needs no @types/node.
declare const process: { env: Record<string, string | undefined> };

const server = process.env.CGVIEW_API ?? 'http://127.0.0.1:8080';

export default defineConfig({
  base: '/',
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2022',
    // draco_decoder.wasm (about 280 KiB) must stay a file of its own.
    assetsInlineLimit: 0,
    // three.js alone is about 500 kB minified.
    chunkSizeWarningLimit: 1024,
  },
  worker: {
    format: 'es',
  },
  server: {
    proxy: {
      '/api': { target: server, ws: true, changeOrigin: true },
    },
  },
  preview: {
    proxy: {
      '/api': { target: server, ws: true, changeOrigin: true },
    },
  },
});
