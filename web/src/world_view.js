// The simulated world's ground truth, drawn faintly for orientation (proto: ws-server/sim_world).
// Built once per world from the server's shape list; the real map replaces it as mapping arrives.
import * as THREE from 'three';

const solidMaterial = () =>
  new THREE.MeshStandardMaterial({
    color: 0xb08d57,
    transparent: true,
    opacity: 0.35,
    depthWrite: false, // the robot stays visible through walls and ceilings
    roughness: 0.9,
  });

function boxMesh(box, material) {
  const mesh = new THREE.Mesh(new THREE.BoxGeometry(...box.size), material);
  mesh.position.set(...box.center);
  mesh.rotation.z = box.yaw;
  mesh.name = box.name;
  return mesh;
}

// A wedge: footprint length x width, top rising from height_start to height_end along the length.
function rampMesh(ramp, material) {
  const l = ramp.length / 2;
  const w = ramp.width / 2;
  const b = ramp.base_z;
  const [hs, he] = [ramp.height_start, ramp.height_end];
  const corners = [
    [-l, -w, b], [l, -w, b], [l, w, b], [-l, w, b], // bottom
    [-l, -w, hs], [l, -w, he], [l, w, he], [-l, w, hs], // top
  ];
  const faces = [
    [0, 2, 1], [0, 3, 2], // bottom
    [4, 5, 6], [4, 6, 7], // top
    [0, 1, 5], [0, 5, 4], // side -w
    [3, 7, 6], [3, 6, 2], // side +w
    [0, 4, 7], [0, 7, 3], // start end
    [1, 2, 6], [1, 6, 5], // far end
  ];
  const positions = faces.flat().flatMap((i) => corners[i]);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.computeVertexNormals();
  const mesh = new THREE.Mesh(geometry, material);
  mesh.position.set(ramp.center[0], ramp.center[1], 0);
  mesh.rotation.z = ramp.yaw;
  mesh.name = ramp.name;
  return mesh;
}

function cylinderMesh(c, material) {
  const height = c.z_max - c.z_min;
  const mesh = new THREE.Mesh(new THREE.CylinderGeometry(c.radius, c.radius, height, 16), material);
  mesh.rotation.x = Math.PI / 2; // three's cylinders stand along y; ours along z
  mesh.position.set(c.center[0], c.center[1], (c.z_min + c.z_max) / 2);
  return mesh;
}

function sphereMesh(s, material) {
  const mesh = new THREE.Mesh(new THREE.SphereGeometry(s.radius, 16, 12), material);
  mesh.position.set(...s.center);
  return mesh;
}

function terrainMesh(t) {
  const geometry = new THREE.PlaneGeometry((t.nx - 1) * t.cell, (t.ny - 1) * t.cell, t.nx - 1, t.ny - 1);
  // PlaneGeometry's vertices run row by row from +y to -y; the heights run from -y (south) up.
  const position = geometry.attributes.position;
  for (let row = 0; row < t.ny; row++) {
    for (let col = 0; col < t.nx; col++) {
      const vertex = row * t.nx + col;
      const height = t.heights[(t.ny - 1 - row) * t.nx + col];
      position.setZ(vertex, height);
    }
  }
  geometry.computeVertexNormals();
  const mesh = new THREE.Mesh(
    geometry,
    new THREE.MeshStandardMaterial({ color: 0x3b4a3a, roughness: 1, flatShading: false }),
  );
  mesh.position.set(t.origin[0] + ((t.nx - 1) * t.cell) / 2, t.origin[1] + ((t.ny - 1) * t.cell) / 2, 0);
  mesh.name = 'terrain';
  return mesh;
}

const fadedMaterial = new THREE.MeshStandardMaterial({
  color: 0xb08d57,
  transparent: true,
  opacity: 0.06,
  depthWrite: false,
});

/** A group holding the whole world, one mesh per shape. */
export function buildWorld(world) {
  const group = new THREE.Group();
  const material = solidMaterial();
  for (const box of world.boxes) group.add(boxMesh(box, material));
  for (const ramp of world.ramps) group.add(rampMesh(ramp, material));
  const trees = new THREE.MeshStandardMaterial({ color: 0x5d8a4e, transparent: true, opacity: 0.35, depthWrite: false });
  for (const c of world.cylinders) group.add(cylinderMesh(c, material));
  for (const s of world.spheres) group.add(sphereMesh(s, trees));
  if (world.terrain) group.add(terrainMesh(world.terrain));
  for (const mesh of group.children) {
    mesh.updateMatrixWorld();
    mesh.userData.bottom = new THREE.Box3().setFromObject(mesh).min.z;
    mesh.userData.material = mesh.material;
  }
  return group;
}

/**
 * Fades what hangs above the robot's head (ceilings, a bridge deck seen from the road) so the robot
 * stays in view: the thesis's "surfaces at the robot's level" (section 3.3.1).
 */
export function fadeAbove(group, height) {
  for (const mesh of group.children) {
    if (mesh.name === 'terrain') continue;
    mesh.material = mesh.userData.bottom > height ? fadedMaterial : mesh.userData.material;
  }
}
