// The parts of an artifact's row in the job list that every kind shares (the
// kinds build their rows from them: kinds/kind.ts): the row with the
// artifact's name and size, the download links of the formats the server
// serves for it, and "Run on this".
import { artifactUrl } from '../api/rest.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { el, formatBytes } from './dom.ts';
import type { JobsActions, JobsView } from './jobs.ts';

type Child = Node | string | null | undefined | false;

/**
 * The formats to download the artifact in: those the server says it serves
 * (its kind's codec), or, from an older server that lists none, the one the
 * kind is stored in.
 */
export function downloadFormats(artifact: ArtifactInfo, storedFormat: string): string[] {
  return artifact.formats?.length ? artifact.formats : [storedFormat];
}

/**
 * An artifact's row: its name (the kind and the stored size as its title),
 * the kind's `controls`, a link per download format (the format's name as
 * its text), and then `content`, what the row shows of the artifact.
 */
export function artifactRow(job: Job, artifact: ArtifactInfo, storedFormat: string, controls: Child[] = [], content: Child = null): HTMLElement {
  const title = artifact.bytes === undefined ? artifact.kind : `${artifact.kind}, ${formatBytes(artifact.bytes)}`;
  const label = el('span', { class: 'artifact-name', title }, artifact.name);
  const links = downloadFormats(artifact, storedFormat).map((f) => el('a', { href: artifactUrl(job.id, artifact.name, f), download: '' }, f));
  return el('div', { class: `artifact artifact-${artifact.kind}`, 'data-artifact': artifact.name }, label, ...controls, ...links, content);
}

/** "Run on this": the artifact (a mesh, a voxel grid) becomes the next job's input. */
export function runOnButton(job: Job, artifact: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLButtonElement {
  const targeted = view.target === `${job.id}/${artifact.name}`;
  const runOn = el(
    'button',
    { type: 'button', class: targeted ? 'button small run-on active' : 'button small run-on', title: 'Run the next algorithm on this result' },
    targeted ? 'Input of next run' : 'Run on this',
  );
  runOn.disabled = targeted;
  runOn.addEventListener('click', () => actions.runOn(job.id, artifact.name));
  return runOn;
}
