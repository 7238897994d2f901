// Two-finger rotate: turning two fingers on the screen turns the map about the vertical axis through the
// point the camera looks at. OrbitControls pinches and pans with two fingers but does not twist.
import * as THREE from 'three';

const zAxis = new THREE.Vector3(0, 0, 1);

export function enableTouchTwist(element, camera, controls) {
  const touches = new Map(); // pointerId -> { x, y }
  let lastAngle = null;
  const angle = () => {
    const [a, b] = [...touches.values()];
    return Math.atan2(b.y - a.y, b.x - a.x);
  };
  element.addEventListener('pointerdown', (event) => {
    if (event.pointerType !== 'touch') return;
    touches.set(event.pointerId, { x: event.clientX, y: event.clientY });
    lastAngle = touches.size === 2 ? angle() : null;
  });
  element.addEventListener('pointermove', (event) => {
    if (!touches.has(event.pointerId)) return;
    touches.set(event.pointerId, { x: event.clientX, y: event.clientY });
    if (touches.size !== 2 || lastAngle === null) return;
    const now = angle();
    let delta = now - lastAngle;
    delta = Math.atan2(Math.sin(delta), Math.cos(delta)); // shortest way round
    lastAngle = now;
    if (Math.abs(delta) < 1e-4) return;
    // Screen y points down, so a clockwise twist on screen is a positive delta: turn the camera with it.
    const offset = camera.position.clone().sub(controls.target).applyAxisAngle(zAxis, delta);
    camera.position.copy(controls.target).add(offset);
    controls.update();
  });
  const lift = (event) => {
    touches.delete(event.pointerId);
    lastAngle = touches.size === 2 ? angle() : null;
  };
  element.addEventListener('pointerup', lift);
  element.addEventListener('pointercancel', lift);
}
