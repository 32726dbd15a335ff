// Loads one of the client's TypeScript modules in node for a unit test: its
// types stripped by the TypeScript compiler. Only for modules that import
// nothing (node cannot resolve the client's `.ts` imports).
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import ts from 'typescript';

const src = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', 'src');

/** Imports src/`file` (e.g. 'api/voxel_slice.ts'). */
export function importTs(file) {
  const { outputText } = ts.transpileModule(fs.readFileSync(path.join(src, file), 'utf8'), {
    compilerOptions: { module: ts.ModuleKind.ESNext, target: ts.ScriptTarget.ES2022 },
    fileName: path.basename(file),
  });
  return import('data:text/javascript;base64,' + Buffer.from(outputText).toString('base64'));
}
