// The progress indicator over the viewport: a bar with its percentage and the
// stage ("uploading", "downloading", "decoding").

export class ProgressPanel {
  private readonly root: HTMLElement;
  private readonly bar: HTMLProgressElement;
  private readonly stage: HTMLElement;
  private readonly percent: HTMLElement;

  constructor(root: HTMLElement) {
    this.root = root;
    this.bar = root.querySelector('progress')!;
    this.stage = root.querySelector('.stage')!;
    this.percent = root.querySelector('.percent')!;
    this.hide();
  }

  /** Shows a stage; `fraction` in 0..1, or null when the amount of work is unknown. */
  show(stage: string, fraction: number | null, what = ''): void {
    this.root.hidden = false;
    this.root.dataset.stage = stage;
    this.stage.textContent = what ? `${stage} ${what}` : stage;
    if (fraction === null) {
      this.bar.removeAttribute('value'); // indeterminate
      this.percent.textContent = '';
    } else {
      const f = Math.min(1, Math.max(0, fraction));
      this.bar.max = 1;
      this.bar.value = f;
      this.percent.textContent = `${Math.floor(f * 100)}%`;
    }
  }

  hide(): void {
    this.root.hidden = true;
    delete this.root.dataset.stage;
  }
}
