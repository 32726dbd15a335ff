// Where a compiler's message goes in the editor: its line and column (as
// g++ counts them: from 1, a tab to the next multiple of 8, a character as
// one) turned into offsets of the editor's text, and the span marked from
// there (the word the column points at). Imports nothing, so that node's
// unit tests load it as it is.

/** The lines of a text, as CodeMirror's Text has them (line n from 1; from/to: offsets in the text). */
export interface DocLines {
  readonly lines: number;
  line(n: number): { from: number; to: number; text: string };
}

/** g++'s default tab stop (-ftabstop). */
export const TAB_SIZE = 8;

/**
 * The index in `text` of the character at 1-based display `column`; the
 * line's end for a column past it, 0 for a column before the first.
 */
export function columnOffset(text: string, column: number, tabSize = TAB_SIZE): number {
  let col = 1;
  let i = 0;
  while (i < text.length && col < column) {
    const code = text.codePointAt(i)!;
    col = code === 9 ? Math.floor((col - 1) / tabSize + 1) * tabSize + 1 : col + 1;
    i += code > 0xffff ? 2 : 1;
  }
  return i;
}

const WORD = /[A-Za-z0-9_]/;

/**
 * The span to mark for a message at `line`, `column` (from 1): from the
 * column to the end of the word there (one character where there is no
 * word); a column of 0 (none given) marks the line from its indentation. A
 * line out of the text is taken as its first or last.
 */
export function diagnosticSpan(doc: DocLines, line: number, column: number): { from: number; to: number } {
  const n = Math.min(Math.max(1, Math.floor(line) || 1), Math.max(1, doc.lines));
  const { from, text } = doc.line(n);
  if (!(column >= 1)) {
    const start = text.length - text.trimStart().length;
    return { from: from + start, to: from + Math.max(start, text.trimEnd().length) };
  }
  const start = columnOffset(text, column);
  let end = start;
  while (end < text.length && WORD.test(text[end]!)) ++end;
  if (end === start && start < text.length) end = start + (text.codePointAt(start)! > 0xffff ? 2 : 1);
  return { from: from + start, to: from + end };
}

/** The editor's lint severity for the compiler's ("fatal error" and the like are errors). */
export function editorSeverity(severity: string): 'error' | 'warning' | 'info' {
  if (severity.includes('error')) return 'error';
  if (severity === 'warning') return 'warning';
  return 'info';
}

/**
 * Whether a message is about the file in the editor: the server compiles it
 * under a plain name (height.cpp), while the headers it includes have paths.
 */
export function inEditedFile(file: string): boolean {
  return file !== '' && !file.includes('/');
}

/** A plain text's lines as DocLines (a newline ends a line; offsets as CodeMirror counts them). */
export function textLines(text: string): DocLines {
  const starts = [0];
  for (let i = 0; i < text.length; ++i) if (text[i] === '\n') starts.push(i + 1);
  return {
    lines: starts.length,
    line(n: number) {
      const from = starts[n - 1]!;
      const to = n < starts.length ? starts[n]! - 1 : text.length;
      return { from, to, text: text.slice(from, to) };
    },
  };
}
