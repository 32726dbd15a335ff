// Uploading: a file picker, and files dropped anywhere on the page.

export const ACCEPTED = ['.off', '.obj', '.ply', '.stl', '.drc', '.glb', '.gltf'];

export class UploadControl {
  constructor(input: HTMLInputElement, dropTarget: HTMLElement, onFiles: (files: File[]) => void) {
    input.accept = ACCEPTED.join(',');
    input.multiple = true;
    input.addEventListener('change', () => {
      const files = [...(input.files ?? [])];
      input.value = ''; // choosing the same file again fires change again
      if (files.length) onFiles(files);
    });

    // dragenter/dragleave fire for every child crossed: count them.
    let depth = 0;
    const hasFiles = (ev: DragEvent) => ev.dataTransfer?.types.includes('Files') ?? false;
    dropTarget.addEventListener('dragenter', (ev) => {
      if (!hasFiles(ev)) return;
      ev.preventDefault();
      if (depth++ === 0) document.body.classList.add('dragging');
    });
    dropTarget.addEventListener('dragover', (ev) => {
      if (!hasFiles(ev)) return;
      ev.preventDefault();
      if (ev.dataTransfer) ev.dataTransfer.dropEffect = 'copy';
    });
    dropTarget.addEventListener('dragleave', () => {
      if (depth > 0 && --depth === 0) document.body.classList.remove('dragging');
    });
    dropTarget.addEventListener('drop', (ev) => {
      ev.preventDefault();
      depth = 0;
      document.body.classList.remove('dragging');
      const files = [...(ev.dataTransfer?.files ?? [])];
      if (files.length) onFiles(files);
    });
  }
}
