// `animation` artifacts (chaos_animate's .frames): fetched over the
// WebSocket as quantized deltas (protocol/API.md, get_animation) and shown as
// points in place of the mesh, with the player's slider and play button over
// the view; the camera frames the box of every frame.
import * as THREE from 'three';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactRow } from '../panels/artifact_row.ts';
import { byId, el } from '../panels/dom.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { AnimationPlayer } from '../viewer/animation_player.ts';
import { decodeFrames, framePositions } from '../viewer/frames.ts';
import type { ArtifactKind } from './kind.ts';

export class AnimationKind implements ArtifactKind {
  readonly kind = 'animation';
  readonly storedFormat = 'frames';
  private readonly ctx: AppContext;
  private readonly player: AnimationPlayer;
  /** The animation being fetched: a later one, or hiding, makes it stale. */
  private token = 0;

  constructor(ctx: AppContext) {
    this.ctx = ctx;
    this.player = new AnimationPlayer(byId('viewport'));
  }

  load(): void {
    // Fetched when played.
  }

  /** "Play": the frames in place of the mesh, with the player. */
  row(job: Job, a: ArtifactInfo, _view: JobsView, actions: JobsActions): HTMLElement {
    const play = el('button', { type: 'button', class: 'button small play-animation' }, 'Play');
    play.addEventListener('click', () => actions.show(job.id, a.name, a.kind));
    return artifactRow(job, a, this.storedFormat, [play]);
  }

  rowState(): null {
    // The row is the same whether the animation plays or not.
    return null;
  }

  async show(jobId: string, artifactName: string): Promise<void> {
    const { app, viewer, hooks, socket } = this.ctx;
    const job = jobOf(this.ctx, jobId);
    if (!job) return;
    const token = ++this.token;
    try {
      const [bytes] = await Promise.all([socket.getAnimation(jobId, artifactName), app.loader.showing]);
      if (token !== this.token) return;
      const frames = decodeFrames(bytes);
      app.compare.leave();
      app.kinds.field.dispose();
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
      viewer.show(points);
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
    this.player.hide();
    this.ctx.hooks.lastAnimation = null;
  }

  dispose(): void {
    this.hide();
  }
}
