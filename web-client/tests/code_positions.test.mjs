// Unit tests of where the code panel marks a compiler's message
// (src/panels/code_positions.ts): g++'s line and column (from 1, tabs to
// the next multiple of 8) as offsets of the editor's text, the word marked,
// lines and columns out of the text, and which messages are about the
// edited file. Also: the panel's template names the algorithm as its
// comments say. `npm run test:unit`.
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { columnOffset, diagnosticSpan, editorSeverity, inEditedFile, textLines, TAB_SIZE } = await importTs('panels/code_positions.ts');
// The template's one home (panels/playground_template.ts imports it as text).
const TEMPLATE = readFileSync(new URL('../../docs/examples/height.cpp', import.meta.url), 'utf8');
const TEMPLATE_NAME = 'height';

test('a column counts characters from 1, a tab to the next tab stop', () => {
  assert.equal(TAB_SIZE, 8);
  assert.equal(columnOffset('abc', 1), 0);
  assert.equal(columnOffset('abc', 3), 2);
  assert.equal(columnOffset('abc', 4), 3, 'just past the end: the end');
  assert.equal(columnOffset('abc', 99), 3, 'far past the end: the end');
  assert.equal(columnOffset('abc', 0), 0);
  assert.equal(columnOffset('abc', -5), 0);
  // A tab at column 1 reaches column 9; one at column 3 as well.
  assert.equal(columnOffset('\tx', 9), 1);
  assert.equal(columnOffset('ab\tx', 9), 3);
  assert.equal(columnOffset('\t\tx', 17), 2);
  assert.equal(columnOffset('\tx', 4, 4), 1, 'another tab size');
  // A character outside the BMP is one column and two UTF-16 units.
  assert.equal(columnOffset('😀x', 2), 2);
  assert.equal(columnOffset('é x', 3), 2);
});

test('textLines cuts a text as the editor does', () => {
  const doc = textLines('ab\n\ncd');
  assert.equal(doc.lines, 3);
  assert.deepEqual(doc.line(1), { from: 0, to: 2, text: 'ab' });
  assert.deepEqual(doc.line(2), { from: 3, to: 3, text: '' });
  assert.deepEqual(doc.line(3), { from: 4, to: 6, text: 'cd' });
  assert.equal(textLines('').lines, 1);
  assert.equal(textLines('x\n').lines, 2);
});

test("a message's span: from its column to the end of the word there", () => {
  const text = 'int main() {\n    field.values[i] = flot(h);\n}\n';
  const doc = textLines(text);
  const span = diagnosticSpan(doc, 2, 23);
  assert.equal(text.slice(span.from, span.to), 'flot');
  // Not on a word: the one character.
  const paren = diagnosticSpan(doc, 2, 27);
  assert.equal(text.slice(paren.from, paren.to), '(');
  // At the line's end: an empty span there.
  const end = diagnosticSpan(doc, 1, 13);
  assert.deepEqual(end, { from: 12, to: 12 });
  // No column: the line from its indentation.
  const line = diagnosticSpan(doc, 2, 0);
  assert.equal(text.slice(line.from, line.to), 'field.values[i] = flot(h);');
});

test('a line out of the text is its first or last; a column past the end, the end', () => {
  const text = 'a b\nlast';
  const doc = textLines(text);
  assert.equal(text.slice(...Object.values(diagnosticSpan(doc, 0, 1))), 'a', 'line 0: the first');
  assert.equal(text.slice(...Object.values(diagnosticSpan(doc, -3, 3))), 'b');
  assert.equal(text.slice(...Object.values(diagnosticSpan(doc, 99, 1))), 'last', 'past the end: the last');
  assert.deepEqual(diagnosticSpan(doc, 2, 50), { from: 8, to: 8 });
  assert.deepEqual(diagnosticSpan(doc, Number.NaN, 1), { from: 0, to: 1 });
  // An empty text still gives a place.
  assert.deepEqual(diagnosticSpan(textLines(''), 3, 4), { from: 0, to: 0 });
});

test('tabs in the line: the column is counted as g++ does', () => {
  const text = '\tx = flot(1);';
  // g++: x at column 9, flot at 13.
  const span = diagnosticSpan(textLines(text), 1, 13);
  assert.equal(text.slice(span.from, span.to), 'flot');
});

test("the compiler's severities as the editor's, and which files are the edited one", () => {
  assert.equal(editorSeverity('error'), 'error');
  assert.equal(editorSeverity('fatal error'), 'error');
  assert.equal(editorSeverity('warning'), 'warning');
  assert.equal(editorSeverity('note'), 'info');
  assert.equal(editorSeverity('anything else'), 'info');
  assert.equal(inEditedFile('height.cpp'), true);
  assert.equal(inEditedFile('registry/registry.h'), false);
  assert.equal(inEditedFile('/usr/include/c++/14/bits/stl_algo.h'), false);
  assert.equal(inEditedFile(''), false);
});

test('the template registers the algorithm its name says, and its float( line is where the e2e test expects', () => {
  assert.equal(TEMPLATE_NAME, 'height');
  assert.match(TEMPLATE, /CGVIEW_REGISTER_FUNCTION\(height, height,/);
  assert.equal(TEMPLATE.split('\n').filter((l) => l.includes('float(')).length, 1, 'one float( line');
  assert.ok(
    TEMPLATE.split('\n').every((l) => l.length <= 120),
    'lines fit the panel',
  );
});
