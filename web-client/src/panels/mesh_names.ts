// Telling meshes of one name apart in the mesh list (two uploads of
// bunny.off): each of them gets a short tag, its upload time, and where that
// is the same too, the first characters of its id. Imports nothing but
// types, so that unit tests can load it.
import type { Mesh } from '../api/types.ts';

/** The characters of an id shown when names and times are the same. */
const ID_CHARS = 6;

/** An upload time, short, in the reader's words: "16:20", with the day ("28 Nov, 16:20") when `withDay`; '' for what is not a time. */
function uploadTime(iso: string, withDay: boolean, timeZone?: string): string {
  const t = new Date(iso);
  if (Number.isNaN(t.getTime())) return '';
  const day: Intl.DateTimeFormatOptions = withDay ? { day: 'numeric', month: 'short' } : {};
  return t.toLocaleString(undefined, { ...day, hour: '2-digit', minute: '2-digit', hourCycle: 'h23', timeZone });
}

/** The day of an upload, to tell whether the times alone say enough. */
function uploadDay(iso: string, timeZone?: string): string {
  const t = new Date(iso);
  return Number.isNaN(t.getTime()) ? '' : t.toLocaleDateString('en-CA', { timeZone });
}

/**
 * A tag for each mesh whose name another mesh of the list has too: its upload
 * time, and the start of its id where the time does not tell it from another
 * one of the name ("16:20 · 3fa2c1"). Meshes of a name of their own get none.
 */
export function repeatedNameTags(meshes: readonly Mesh[], timeZone?: string): Map<string, string> {
  const byName = new Map<string, Mesh[]>();
  for (const m of meshes) byName.set(m.name, [...(byName.get(m.name) ?? []), m]);
  const tags = new Map<string, string>();
  for (const group of byName.values()) {
    if (group.length < 2) continue;
    const days = new Set(group.map((m) => uploadDay(m.created, timeZone)));
    const times = group.map((m) => uploadTime(m.created, days.size > 1, timeZone));
    group.forEach((m, i) => {
      const time = times[i]!;
      const unique = time !== '' && times.filter((t) => t === time).length === 1;
      tags.set(m.id, unique ? time : [time, m.id.slice(0, ID_CHARS)].filter(Boolean).join(' · '));
    });
  }
  return tags;
}
