// `text` artifacts (chaos_extract's message): fetched when the job is done and
// shown in the job list. Not necessarily UTF-8: undecodable bytes show as
// U+FFFD.
import { fetchArtifactBytes } from '../api/rest.ts';
import type { AppContext } from '../controllers/context.ts';
import { el } from '../panels/dom.ts';
import { ListedKind, type Listed } from './listed.ts';
import { KindSlice } from './slice.ts';

export class TextKind extends ListedKind<string> {
  readonly kind = 'text';
  readonly storedFormat = 'txt';

  constructor(ctx: AppContext) {
    super(ctx, new KindSlice<Listed>('text', new Map()));
  }

  protected async fetch(jobId: string, name: string): Promise<string> {
    return new TextDecoder('utf-8').decode(await fetchArtifactBytes(jobId, name, 'txt'));
  }

  /** The text itself, under its download links: at most 2000 characters here; the links have all the bytes. */
  protected content(text: string | undefined): HTMLElement {
    const shown = text === undefined ? 'loading…' : text.length > 2000 ? `${text.slice(0, 2000)}…` : text;
    return el('pre', { class: 'text-content' }, shown);
  }
}
