// The scene's lights, and the same lighting worked out per face for the map, whose geometry carries it in
// its vertex colours: an unlit material then draws it for a fraction of a lit one's per-pixel cost, which
// is what a robot's modest (or software) GPU spends most of a frame of a big map on.
import * as THREE from 'three';

const SKY = new THREE.Color(0xdde6ff);
const GROUND = new THREE.Color(0x202020);
const HEMISPHERE_INTENSITY = 1.6;
const SUN = new THREE.Color(0xffffff);
const SUN_INTENSITY = 1.5;
const SUN_POSITION = new THREE.Vector3(6, -8, 12);

/** The hemisphere light and the sun, for the scene. */
export function createLights() {
  // The hemisphere light keeps three's default direction (+y), as it always has here: the map's baked
  // colours below match it.
  const hemisphere = new THREE.HemisphereLight(SKY, GROUND, HEMISPHERE_INTENSITY);
  const sun = new THREE.DirectionalLight(SUN, SUN_INTENSITY);
  sun.position.copy(SUN_POSITION);
  return [hemisphere, sun];
}

const hemisphereDirection = new THREE.Vector3(0, 1, 0);
const sunDirection = SUN_POSITION.clone().normalize();

/**
 * What a Lambert material under createLights() reflects from a face with this (unit) normal, per colour
 * channel in linear RGB: three's irradiance times its Lambert BRDF (1 / pi).
 */
export function lambertShade(normal) {
  const weight = 0.5 * normal.dot(hemisphereDirection) + 0.5;
  const irradiance = GROUND.clone().lerp(SKY, weight).multiplyScalar(HEMISPHERE_INTENSITY);
  irradiance.add(SUN.clone().multiplyScalar(SUN_INTENSITY * Math.max(normal.dot(sunDirection), 0)));
  return irradiance.multiplyScalar(1 / Math.PI);
}
