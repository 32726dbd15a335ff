// `animation` artifacts (chaos_animate's .frames): fetched over the
// WebSocket as quantized deltas (protocol/API.md, get_animation) and shown as
// points in place of the mesh, with the player's slider and play button over
// the view; the camera frames the box of every frame. "Play" in the job list
// plays it at once (and pauses it, as "Pause", while it plays); once something
// else takes the points' place, the player goes with them.
import * as THREE from 'three';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactRow } from '../panels/artifact_row.ts';
import { byId, el } from '../panels/dom.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { AnimationPlayer } from '../viewer/animation_player.ts';
import { decodeFrames, framePositions } from '../viewer/frames.ts';
import { type ArtifactKind, type KindDeps } from './kind.ts';
import { type ScalarFieldKind } from './scalar_field.ts';

export class AnimationKind implements ArtifactKind {
  readonly kind = 'animation';
  readonly storedFormat = 'frames';
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: KindDeps;
  /** The scalar fields' kind: an animation replaces the field drawn. */
  private readonly field: Pick<ScalarFieldKind, 'dispose'>;
  private readonly player: AnimationPlayer;
  /** The animation being fetched: a later one, or hiding, makes it stale. */
  private token = 0;
  /** The animation shown, as `${jobId}/${artifact}`, and its points. */
  private shown: { key: string; points: THREE.Points } | null = null;

  constructor(ctx: AppContext, deps: KindDeps, field: Pick<ScalarFieldKind, 'dispose'>) {
    this.ctx = ctx;
    this.deps = deps;
    this.field = field;
    this.player = new AnimationPlayer(byId('viewport'), () => this.syncButtons());
    ctx.viewer.onShownChange((object) => {
      if (this.shown && object !== this.shown.points) this.hide();
    });
  }

  load(): void {
    // Fetched when played.
  }

  /** "Play": the frames in place of the mesh, with the player. */
  row(job: Job, a: ArtifactInfo, _view: JobsView, _actions: JobsActions): HTMLElement {
    const key = `${job.id}/${a.name}`;
    const play = el('button', { type: 'button', class: 'button small play-animation', 'data-key': key }, this.label(key));
    play.addEventListener('click', () => void this.toggle(job.id, a.name));
    return artifactRow(job, a, this.storedFormat, [play]);
  }

  /** The job list's button: plays the animation (shown first, if it is not), or pauses it while it plays. */
  private async toggle(jobId: string, artifact: string): Promise<void> {
    const key = `${jobId}/${artifact}`;
    if (this.shown?.key === key) {
      if (this.player.playing) this.player.stop();
      else this.player.start();
      return;
    }
    // show() takes the next token at once when it begins a fetch; play once that fetch is shown, if nothing came after it.
    const token = this.token + 1;
    const shown = this.show(jobId, artifact);
    if (this.token !== token) return;
    await shown;
    if (this.token === token && this.shown?.key === key) this.player.start();
  }

  private label(key: string): string {
    return this.shown?.key === key && this.player.playing ? 'Pause' : 'Play';
  }

  /** The job list's buttons say what pressing them does now. */
  private syncButtons(): void {
    for (const b of document.querySelectorAll<HTMLButtonElement>('button.play-animation')) b.textContent = this.label(b.dataset.key ?? '');
  }

  rowState(): null {
    // The row's button follows the player in place (syncButtons): the row itself stays as built.
    return null;
  }

  async show(jobId: string, artifactName: string): Promise<void> {
    const { viewer, hooks, socket } = this.ctx;
    const { deps } = this;
    const job = jobOf(this.ctx, jobId);
    if (!job) return;
    const token = ++this.token;
    try {
      const [bytes] = await Promise.all([socket.getAnimation(jobId, artifactName), deps.loader.showing]);
      if (token !== this.token) return;
      const frames = decodeFrames(bytes);
      deps.leaveComparison();
      this.field.dispose();
      const positions = framePositions(frames, 0, new Float32Array(3 * frames.vertices));
      const geometry = new THREE.BufferGeometry();
      const attribute = new THREE.BufferAttribute(positions, 3);
      attribute.setUsage(THREE.DynamicDrawUsage);
      geometry.setAttribute('position', attribute);
      // The box of every frame, so that fit-to-view and culling hold for all.
      geometry.boundingBox = new THREE.Box3(new THREE.Vector3(...frames.lo), new THREE.Vector3(...frames.hi));
      geometry.boundingSphere = geometry.boundingBox.getBoundingSphere(new THREE.Sphere());
      const size = geometry.boundingSphere.radius / 150;
      const points = new THREE.Points(geometry, new THREE.PointsMaterial({ color: '#e07a1f', size, sizeAttenuation: true }));
      points.name = 'animation';
      hooks.lastAnimation = null;
      this.ctx.textures.detach();
      // Replaced on purpose: the player is shown again below, not hidden as for another object.
      this.shown = null;
      viewer.show(points);
      this.shown = { key: `${jobId}/${artifactName}`, points };
      this.player.show(`${job.algorithm} · ${artifactName}`, frames.frames, (k) => {
        if (viewer.object !== points) return;
        framePositions(frames, k, positions);
        attribute.needsUpdate = true;
        viewer.redraw(() => {
          if (viewer.object !== points) return;
          let sum = 0;
          for (let i = 0; i < positions.length; ++i) sum += positions[i]!;
          hooks.lastAnimation = {
            jobId,
            artifact: artifactName,
            frame: k,
            frames: frames.frames,
            vertices: frames.vertices,
            first: [positions[0]!, positions[1]!, positions[2]!],
            sum,
          };
        });
      });
    } catch (e) {
      if (token !== this.token) return;
      this.ctx.error(`Cannot show ${artifactName} of ${job.algorithm}: ${describe(e)}`);
    }
  }

  hide(): void {
    ++this.token;
    this.shown = null;
    this.player.hide();
    this.syncButtons();
    this.ctx.hooks.lastAnimation = null;
  }

  dispose(): void {
    this.hide();
  }
}
