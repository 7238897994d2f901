// Save, Load and Download: one dialog in three modes for the map files.
import { defaultMapName, downloadUrl, fetchRosMap, listMaps, NAME_PATTERN } from './map_files.js';

const $ = (id) => document.getElementById(id);

/** `command(message)` sends an operator command; `notices` says what went wrong. */
export function setUpFilesDialog({ command, notices }) {
  const dialog = $('files-dialog');
  let mode = null;

  function open(newMode, title) {
    mode = newMode;
    $('files-title').textContent = title;
    $('files-save').hidden = mode !== 'save';
    $('files-load').hidden = mode !== 'load';
    $('files-download').hidden = mode !== 'download';
    dialog.showModal();
  }

  $('map-save').addEventListener('click', () => {
    $('save-name').value = defaultMapName();
    open('save', 'Save the map');
  });
  $('map-load').addEventListener('click', async () => {
    let maps;
    try {
      maps = await listMaps();
    } catch (error) {
      notices.serverError({ ...error, request: 'load_map' });
      return;
    }
    const select = $('load-name');
    select.replaceChildren(
      ...maps.map((map) => {
        const option = new Option(`${map.name} · ${(map.bytes / 1024).toFixed(0)} KiB · ${new Date(map.modified * 1000).toLocaleString()}`, map.name);
        return option;
      }),
    );
    if (maps.length) select.selectedIndex = 0;
    else notices.show('No saved maps yet', 'info', 4);
    open('load', 'Load a saved map');
  });
  $('map-download').addEventListener('click', () => open('download', 'Download the map'));

  dialog.addEventListener('close', () => {
    if (dialog.returnValue !== 'ok') return;
    if (mode === 'save') {
      const name = $('save-name').value.trim();
      if (!NAME_PATTERN.test(name)) {
        notices.show('A map name is a plain file name: letters, digits, . - _ (up to 64)', 'error');
        return;
      }
      command({ op: 'save_map', name });
    } else if (mode === 'load') {
      const name = $('load-name').value;
      // Mapping goes on in the loaded map; localizing keeps it as saved and places the robot in it.
      const loadMode = document.querySelector('input[name="load-mode"]:checked')?.value ?? 'mapping';
      if (name) command({ op: 'load_map', name, mode: loadMode });
    } else if (mode === 'download') {
      const format = $('download-format').value;
      if (format === 'ros') downloadRosMap(notices);
      else save(downloadUrl(format), '');
    }
  });
}

function save(href, name) {
  const link = document.createElement('a');
  link.href = href;
  link.download = name;
  link.click();
}

/** map.yaml and the map.pgm it names, of one map version (the server's names, so map_server reads them as
 * they land side by side). */
async function downloadRosMap(notices) {
  let map;
  try {
    map = await fetchRosMap();
  } catch (error) {
    notices.serverError({ ...error, request: 'download' });
    return;
  }
  for (const [blob, name] of [
    [map.yaml, 'map.yaml'],
    [map.pgm, 'map.pgm'],
  ]) {
    const url = URL.createObjectURL(blob);
    save(url, name);
    setTimeout(() => URL.revokeObjectURL(url), 60000);
  }
  notices.show(`Drivable map of version ${map.version}: map.yaml and map.pgm`, 'info', 4);
}
