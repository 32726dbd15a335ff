// The code panel's editor: CodeMirror 6 with C++ highlighting, and the
// compiler's messages marked at their places (underlined, a marker in the
// gutter, the message on hover). Loaded with the panel only (a chunk of its
// own), so that the viewer's first load does not carry it.
import { cpp } from '@codemirror/lang-cpp';
import { lintGutter, setDiagnostics, type Diagnostic } from '@codemirror/lint';
import { Compartment, EditorSelection, EditorState, type Extension } from '@codemirror/state';
import { oneDark } from '@codemirror/theme-one-dark';
import { EditorView } from '@codemirror/view';
import { basicSetup } from 'codemirror';
import type { PluginDiagnostic } from '../api/plugins.ts';
import { diagnosticSpan, editorSeverity, inEditedFile } from './code_positions.ts';

export class CodeEditor {
  readonly view: EditorView;
  private readonly editable = new Compartment();
  private readonly extensions: Extension[];

  /** `onChange`: the text was edited (not when set with setText). */
  constructor(parent: HTMLElement, text: string, onChange: () => void) {
    this.extensions = [
      basicSetup,
      cpp(),
      oneDark,
      lintGutter(),
      this.editable.of(EditorState.readOnly.of(false)),
      EditorView.contentAttributes.of({ 'aria-label': 'C++ source' }),
      EditorView.updateListener.of((u) => {
        if (u.docChanged) onChange();
      }),
    ];
    this.view = new EditorView({ parent, state: EditorState.create({ doc: text, extensions: this.extensions }) });
  }

  get text(): string {
    return this.view.state.doc.toString();
  }

  /** Replaces the whole text (another file opened): no messages, the cursor at the start, no undo back into the old file. */
  setText(text: string, readOnly: boolean): void {
    this.view.setState(EditorState.create({ doc: text, extensions: this.extensions }));
    if (readOnly) this.setReadOnly(true);
  }

  setReadOnly(readOnly: boolean): void {
    this.view.dispatch({ effects: this.editable.reconfigure(EditorState.readOnly.of(readOnly)) });
  }

  /**
   * Marks the messages about this file at their places; those of other files
   * (the headers) are listed by the panel only. Returns how many were marked.
   */
  showDiagnostics(messages: readonly PluginDiagnostic[]): number {
    const doc = this.view.state.doc;
    const marks: Diagnostic[] = [];
    for (const d of messages) {
      if (!inEditedFile(d.file)) continue;
      const { from, to } = diagnosticSpan(doc, d.line, d.column);
      marks.push({ from, to, severity: editorSeverity(d.severity), message: d.message, source: d.severity });
    }
    this.view.dispatch(setDiagnostics(this.view.state, marks));
    return marks.length;
  }

  /** Puts the cursor on a message's word (selected), in view, and the focus in the editor. */
  goTo(line: number, column: number): void {
    const { from, to } = diagnosticSpan(this.view.state.doc, line, column);
    this.view.dispatch({ selection: EditorSelection.single(from, to), scrollIntoView: true });
    this.view.focus();
  }
}
