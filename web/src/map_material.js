// The map's materials: the least a fragment can cost, since a software GPU spends most of a big map's frame
// on them. Colours arrive per vertex with the lighting already in them (lights.js) and already in sRGB
// (tile_geometry.js), so the fragment shader only writes its colour: no lights, and no per-pixel colour
// space conversion (three's materials convert linear to sRGB per pixel, three pow() each).
import * as THREE from 'three';

const vertexShader = `
precision highp float;
uniform mat4 modelViewMatrix;
uniform mat4 projectionMatrix;
attribute vec3 position;
attribute vec3 color;
varying vec3 vColor;
void main() {
  vColor = color;
  gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
}`;

const fragmentShader = `
precision mediump float;
varying vec3 vColor;
void main() {
  gl_FragColor = vec4(vColor, 1.0);
}`;

/**
 * [floors, walls]: the material groups of tile_geometry.js's geometries. Floors are seen from above and,
 * under a deck, from below; a wall box is closed, so only the sides facing the camera are drawn.
 */
export function createMapMaterials() {
  const material = (side) => new THREE.RawShaderMaterial({ vertexShader, fragmentShader, side });
  return [material(THREE.DoubleSide), material(THREE.FrontSide)];
}
