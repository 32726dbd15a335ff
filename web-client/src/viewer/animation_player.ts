// The animation player over the viewport: a title, a play/pause button and a
// slider over the frames (chaos_animate's frames, the paper's Figure 11).
// Playing steps through the frames on a timer until the last one.
export class AnimationPlayer {
  private readonly root: HTMLElement;
  private readonly title: HTMLElement;
  private readonly play: HTMLButtonElement;
  private readonly slider: HTMLInputElement;
  private readonly label: HTMLElement;
  private timer: number | null = null;
  private onFrame: ((k: number) => void) | null = null;
  /** Told when playing starts or stops (the job list's "Play" says "Pause" meanwhile). */
  private readonly onPlaying: (playing: boolean) => void;

  constructor(container: HTMLElement, onPlaying: (playing: boolean) => void = () => {}) {
    this.onPlaying = onPlaying;
    this.root = document.createElement('div');
    this.root.className = 'player';
    this.root.id = 'animation-player';
    this.root.hidden = true;
    this.title = document.createElement('div');
    this.title.className = 'player-title';
    this.play = document.createElement('button');
    this.play.type = 'button';
    this.play.className = 'button small player-play';
    this.play.textContent = 'Play';
    this.play.addEventListener('click', () => (this.timer === null ? this.start() : this.stop()));
    this.slider = document.createElement('input');
    this.slider.type = 'range';
    this.slider.className = 'player-slider';
    this.slider.min = '0';
    this.slider.step = '1';
    this.slider.setAttribute('aria-label', 'Frame');
    this.slider.addEventListener('input', () => this.go(Number(this.slider.value)));
    this.label = document.createElement('span');
    this.label.className = 'player-frame';
    const row = document.createElement('div');
    row.className = 'player-row';
    row.append(this.play, this.slider, this.label);
    this.root.append(this.title, row);
    container.append(this.root);
  }

  /** Shows the player for `frames` frames (0 .. frames-1) at frame 0. */
  show(title: string, frames: number, onFrame: (k: number) => void): void {
    this.stop();
    this.onFrame = onFrame;
    this.title.textContent = title;
    this.slider.max = String(Math.max(0, frames - 1));
    this.root.hidden = false;
    this.go(0);
  }

  get playing(): boolean {
    return this.timer !== null;
  }

  /** Plays from the frame shown (from the first, when at the last). */
  start(): void {
    if (this.timer !== null || !this.onFrame) return;
    if (Number(this.slider.value) >= Number(this.slider.max)) this.go(0);
    this.timer = window.setInterval(() => {
      const k = Math.min(Number(this.slider.value) + 1, Number(this.slider.max));
      this.go(k);
      if (k >= Number(this.slider.max)) this.stop(); // the last frame stays shown
    }, 150);
    this.playingChanged();
  }

  /** Pauses on the frame shown. */
  stop(): void {
    if (this.timer === null) return;
    window.clearInterval(this.timer);
    this.timer = null;
    this.playingChanged();
  }

  hide(): void {
    this.stop();
    this.onFrame = null;
    this.root.hidden = true;
  }

  private go(k: number): void {
    this.slider.value = String(k);
    this.label.textContent = `step ${k} / ${this.slider.max}`;
    this.onFrame?.(k);
  }

  private playingChanged(): void {
    const playing = this.timer !== null;
    this.play.textContent = playing ? 'Pause' : 'Play';
    this.onPlaying(playing);
  }
}
