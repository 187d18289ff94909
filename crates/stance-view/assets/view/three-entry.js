// What the viewer uses of three.js: scripts/vendor-three.sh bundles exactly these names (and
// what they need) into three.min.js, one classic script that defines the global THREE.
export {
  AmbientLight, ArrowHelper, BoxGeometry, BufferGeometry, CanvasTexture, CapsuleGeometry, Color,
  CylinderGeometry, DirectionalLight, DoubleSide, EdgesGeometry, Float32BufferAttribute,
  GridHelper, Group, HemisphereLight, Line, LineBasicMaterial, LineSegments, Matrix4, Mesh,
  MeshBasicMaterial, MeshStandardMaterial, PerspectiveCamera, Quaternion, Scene, SphereGeometry,
  Sprite, SpriteMaterial, Vector3, WebGLRenderer, REVISION,
} from 'three';
export { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
