// The 3D map (GET /api/v1/map/octomap) in a three.js view: each occupied voxel a cube coloured by its height, the
// robot a blue post, orbit with the mouse. Fetched only while its panel is open, and again when the octree's
// revision changes (the daemon takes a new snapshot every couple of seconds while it grows).
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

import { request, send, type Octomap, type Pose } from './api';
import { byId } from './dom';

const kPollMs = 3000;
const kTopColourM = 2.0;  // heights from 0 to this go from blue to red

export class OctomapView {
  private renderer: THREE.WebGLRenderer | null = null;
  private readonly scene = new THREE.Scene();
  private readonly camera = new THREE.PerspectiveCamera(50, 1, 0.05, 500);
  private controls: OrbitControls | null = null;
  private voxels: THREE.InstancedMesh | null = null;
  private readonly robot: THREE.Mesh;
  private revision = -1;
  private centred = false;
  private timer = 0;

  constructor(private readonly panel: HTMLDetailsElement, private readonly host: HTMLElement) {
    this.camera.up.set(0, 0, 1);  // the map frame: z up
    this.scene.background = new THREE.Color(0x0d1117);
    this.scene.add(new THREE.AmbientLight(0xffffff, 0.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.2);
    sun.position.set(5, 3, 10);
    this.scene.add(sun);
    this.robot = new THREE.Mesh(new THREE.CylinderGeometry(0.2, 0.2, 0.4, 24).rotateX(Math.PI / 2),
      new THREE.MeshLambertMaterial({ color: 0x1f6feb }));
    this.scene.add(this.robot);
    panel.addEventListener('toggle', () => (panel.open ? this.open() : this.close()));
  }

  // Where the robot is now (from the state stream).
  showRobot(pose: Pose | null): void {
    if (!pose) return;
    this.robot.position.set(pose.x, pose.y, 0.2);
    if (this.renderer && !this.centred) this.centre(pose.x, pose.y);
  }

  private open(): void {
    if (!this.renderer) {
      try {
        this.renderer = new THREE.WebGLRenderer({ antialias: true });
        this.host.appendChild(this.renderer.domElement);
        this.controls = new OrbitControls(this.camera, this.renderer.domElement);
        this.controls.addEventListener('change', () => this.render());
        if (this.robot.position.lengthSq() > 0) this.centre(this.robot.position.x, this.robot.position.y);
      } catch (e) {
        // Without WebGL the figures below still come.
        this.host.textContent = `no 3D view in this browser: ${(e as Error).message}`;
      }
    }
    const width = this.host.clientWidth || 300;
    const height = Math.round(width * 0.75);
    this.renderer?.setSize(width, height);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
    void this.poll();
  }

  private close(): void {
    window.clearTimeout(this.timer);
  }

  private centre(x: number, y: number): void {
    this.centred = true;
    this.camera.position.set(x - 4, y - 4, 4);
    this.controls?.target.set(x, y, 0);
    this.controls?.update();
    this.render();
  }

  private async poll(): Promise<void> {
    window.clearTimeout(this.timer);
    const status = byId('octomap-status');
    try {
      const info = await send<Octomap>('GET', '/api/v1/map/octomap');
      if (info.revision !== this.revision) {
        const res = await request(info.voxels_url, { cache: 'no-store' });
        if (!res.ok) throw new Error(`voxels: HTTP ${res.status}`);
        this.show(new Float32Array(await res.arrayBuffer()));
        this.revision = info.revision;
      }
      status.textContent = `'${info.map}': ${info.occupied} occupied voxels of ${info.resolution_m * 100} cm, ` +
        `${info.leaves} leaves`;
      byId<HTMLAnchorElement>('octomap-download').href = info.bt_url;
    } catch (e) {
      status.textContent = (e as Error).message;
    }
    if (this.panel.open) this.timer = window.setTimeout(() => void this.poll(), kPollMs);
  }

  private show(data: Float32Array): void {
    const count = data.length / 4;
    if (this.voxels) {
      this.scene.remove(this.voxels);
      this.voxels.dispose();
    }
    const mesh = new THREE.InstancedMesh(new THREE.BoxGeometry(1, 1, 1), new THREE.MeshLambertMaterial(), count);
    const matrix = new THREE.Matrix4();
    const colour = new THREE.Color();
    for (let i = 0; i < count; ++i) {
      const [x, y, z, size] = [data[4 * i], data[4 * i + 1], data[4 * i + 2], data[4 * i + 3]];
      matrix.makeScale(size, size, size).setPosition(x, y, z);
      mesh.setMatrixAt(i, matrix);
      colour.setHSL(0.66 * (1 - Math.min(1, Math.max(0, z / kTopColourM))), 0.8, 0.5);
      mesh.setColorAt(i, colour);
    }
    mesh.instanceMatrix.needsUpdate = true;
    if (mesh.instanceColor) mesh.instanceColor.needsUpdate = true;
    this.voxels = mesh;
    this.scene.add(mesh);
    this.host.dataset.voxels = String(count);
    this.render();
  }

  private render(): void {
    this.renderer?.render(this.scene, this.camera);
  }
}
