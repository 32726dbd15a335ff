// An assignment's statement, written in Markdown by its teacher: parsed by
// marked (GitHub's flavour) and sanitized by DOMPurify into DOM nodes (no
// script, no handler, no javascript: link survives), so that nothing a
// statement holds runs in the student's page. Links open in a new tab.
// Loaded with the first statement shown (a chunk of its own).
import DOMPurify from 'dompurify';
import { Marked } from 'marked';

const marked = new Marked({ gfm: true, breaks: false, async: false });

/** The statement as DOM nodes, sanitized. */
export function renderMarkdown(text: string): DocumentFragment {
  const html = marked.parse(text, { async: false });
  const fragment = DOMPurify.sanitize(html, { RETURN_DOM_FRAGMENT: true, FORBID_TAGS: ['style', 'form', 'button', 'iframe'] });
  for (const a of fragment.querySelectorAll('a[href]')) {
    a.setAttribute('target', '_blank');
    a.setAttribute('rel', 'noopener noreferrer');
  }
  return fragment;
}
