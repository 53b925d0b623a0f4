// Files dropped on the page are imported: one file (.bvh, .glb, .obj, .fbx, a
// self-contained .gltf) as the body of POST /v1/assets:import?filename=…, several
// (a .gltf and its buffers and images) as one multipart form, as the gateway
// takes them. The upload's progress shows in a <progress> and its label (XHR:
// fetch reports no upload progress). Emits 'imported' (the ImportAssetResponse)
// 'error' (a message) and 'progress' (the fraction uploaded).

// Sends `files` (File objects) to the import route; `onProgress(fraction)` as bytes go.
export function importFiles(files, onProgress) {
  return new Promise((resolve, reject) => {
    const xhr = new XMLHttpRequest();
    let body;
    if (files.length === 1) {
      xhr.open('POST', `/v1/assets:import?${new URLSearchParams({ filename: files[0].name })}`);
      xhr.setRequestHeader('Content-Type', 'application/octet-stream');
      body = files[0];
    } else {
      xhr.open('POST', '/v1/assets:import');
      body = new FormData();
      for (const file of files) body.append('files', file, file.name);
    }
    xhr.upload.onprogress = (event) => event.lengthComputable && onProgress(event.loaded / event.total);
    xhr.onload = () => {
      let answer = null;
      try {
        answer = JSON.parse(xhr.responseText);
      } catch {
        // not JSON: reported below by the status
      }
      if (xhr.status >= 200 && xhr.status < 300 && answer) resolve(answer);
      else reject(new Error(answer?.message ?? `${xhr.status} ${xhr.statusText}`));
    };
    xhr.onerror = () => reject(new Error('the upload was interrupted'));
    xhr.send(body);
  });
}

export class DropImport extends EventTarget {
  // `target`: the element files are dropped on; `progress`: a <progress>;
  // `label`: an element for the file's name and percentage.
  constructor(target, { progress, label }) {
    super();
    this.target = target;
    this.progress = progress;
    this.label = label;
    this.busy = false;
    let depth = 0;  // dragenter/dragleave pairs of nested elements
    const carriesFiles = (event) => [...(event.dataTransfer?.types ?? [])].includes('Files');
    target.addEventListener('dragenter', (event) => {
      if (!carriesFiles(event)) return;
      event.preventDefault();
      if (++depth === 1) target.classList.add('dropping');
    });
    target.addEventListener('dragover', (event) => {
      if (!carriesFiles(event)) return;
      event.preventDefault();
      event.dataTransfer.dropEffect = 'copy';
    });
    target.addEventListener('dragleave', () => {
      if (depth > 0 && --depth === 0) target.classList.remove('dropping');
    });
    target.addEventListener('drop', (event) => {
      event.preventDefault();
      depth = 0;
      target.classList.remove('dropping');
      const files = [...(event.dataTransfer?.files ?? [])];
      if (files.length) this.upload(files);
    });
  }

  // Imports `files`, showing progress; one import at a time.
  async upload(files) {
    if (this.busy) {
      this.emit('error', 'an import is already running');
      return;
    }
    this.busy = true;
    const what = files.length === 1 ? files[0].name : `${files.length} files`;
    const show = (fraction) => {
      this.emit('progress', fraction);
      this.progress.hidden = this.label.hidden = false;
      this.progress.value = fraction;
      this.label.textContent =
        fraction < 1 ? `Importing ${what}: ${Math.round(fraction * 100)}%` : `Importing ${what}: reading it…`;
    };
    show(0);
    try {
      const answer = await importFiles(files, show);
      this.label.textContent = `Imported ${answer.asset?.name ?? what}`;
      this.emit('imported', answer);
    } catch (error) {
      this.label.textContent = `Import of ${what} failed`;
      this.emit('error', error.message);
    } finally {
      this.busy = false;
      this.progress.hidden = true;
    }
  }

  emit(type, detail) {
    this.dispatchEvent(new CustomEvent(type, { detail }));
  }
}
