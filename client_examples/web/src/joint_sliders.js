// JointSliders: live posing. A joint picked from the model's joints is turned by three sliders
// (degrees about x, y and z, after its rest rotation); every joint turned so far stays turned.
// setJoints(names, restRotations): the model's joint names and rest rotations (THREE.Quaternion
// each). rotations(): {names, rotations} of the turned joints, local {x, y, z, w}, for
// PoseByName. onChange() runs when a slider moves or reset() turns every joint back to rest.
import * as THREE from 'three';

export class JointSliders {
  constructor(select, sliders, onChange) {
    this.select = select;
    this.sliders = sliders;  // the x, y and z <input type=range>, degrees
    this.onChange = onChange;
    this.turns = new Map();  // joint name -> [x, y, z] degrees
    this.rest = new Map();   // joint name -> THREE.Quaternion
    select.addEventListener('change', () => this.showJoint());
    for (const slider of sliders) slider.addEventListener('input', () => this.turnJoint());
  }

  setJoints(names, restRotations) {
    this.select.replaceChildren(...names.map((name) => new Option(name, name)));
    names.forEach((name, i) => this.rest.set(name, restRotations[i]));
    this.showJoint();
  }

  showJoint() {
    const turn = this.turns.get(this.select.value) ?? [0, 0, 0];
    this.sliders.forEach((slider, axis) => { slider.value = turn[axis]; });
  }

  turnJoint() {
    this.turns.set(this.select.value, this.sliders.map((slider) => Number(slider.value)));
    this.onChange();
  }

  reset() {
    this.turns.clear();
    this.showJoint();
    this.onChange();
  }

  rotations() {
    const names = [];
    const rotations = [];
    for (const [name, degrees] of this.turns) {
      const [x, y, z] = degrees.map(THREE.MathUtils.degToRad);
      const turn = new THREE.Quaternion().setFromEuler(new THREE.Euler(x, y, z));
      names.push(name);
      rotations.push(this.rest.get(name).clone().multiply(turn));
    }
    return { names, rotations };
  }
}
