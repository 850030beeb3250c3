// sweepd's browser viewer: connects to sweepd over WebSocket, shows the model's rest mesh and
// then its poses, deformed by sweep, LBS and DQS side by side: a clip uploaded from a BVH file
// and played on the server (PoseFromClip), or joints turned with the sliders (PoseByName); or,
// with ?stream=NAME, the frames of a VMC stream sweepd receives (SubscribeStream).
import * as THREE from 'three';
import { BodyViews } from './body_views.js';
import { ClipPlayer } from './clip_player.js';
import { JointSliders } from './joint_sliders.js';
import { PageStatus } from './page_status.js';
import { PoseStream } from './pose_stream.js';
import { bodyAs, listModels, loadModel, meshRequest, pb, poseByName, poseFromClip,
         uploadClip } from './protocol_messages.js';
import { StreamStats } from './stream_stats.js';
import { StreamWatch } from './stream_watch.js';
import { SweepdConnection } from './sweepd_connection.js';
import { readUrlOptions } from './url_options.js';
import { decoderReady } from './vertex_decoding.js';

const element = (id) => document.getElementById(id);
const status = new PageStatus(element('status'), element('stats'));

// The model named in the URL, else "mannequin" when held, else the first held.
async function chooseModel(connection, wanted) {
  const list = bodyAs(await connection.request((id) => listModels(id)), pb.ModelList);
  const names = [];
  for (let i = 0; i < list.modelsLength(); ++i) {
    if (list.models(i).modelId() !== 0) names.push(list.models(i).name());
  }
  const name = wanted ?? (names.includes('mannequin') ? 'mannequin' : names[0]);
  if (!name) throw new Error('sweepd holds no model');
  return bodyAs(await connection.request((id) => loadModel(id, name)), pb.ModelInfo);
}

function restRotations(info) {
  const rotations = [];
  for (let i = 0; i < info.jointRestRotationsLength(); ++i) {
    const q = info.jointRestRotations(i);
    rotations.push(new THREE.Quaternion(q.x(), q.y(), q.z(), q.w()));
  }
  return rotations;
}

function jointNames(info) {
  return Array.from({ length: info.jointNamesLength() }, (_, i) => info.jointNames(i));
}

// The method checkboxes, checked as the URL says; `show(methods)` whenever they change.
function followMethodBoxes(options, show) {
  const methodBoxes = [...element('methods').querySelectorAll('input')];
  methodBoxes.forEach((box) => { box.checked = options.methods.includes(box.value); });
  const showChecked = () => show(methodBoxes.filter((box) => box.checked).map((box) => box.value));
  methodBoxes.forEach((box) => box.addEventListener('change', showChecked));
  showChecked();
}

// ?stream=NAME: the stream's frames as they arrive; the clip and joint controls are hidden (the
// page a streamer adds to OBS as a browser source).
function watchStream(options, connection, modelId, views, stats) {
  document.body.classList.add('watching');
  // The subscriptions have their own connections; this one, idle from here on, would be cut.
  connection.close();
  const watch = new StreamWatch({
    url: options.ws, token: options.token, stream: options.stream, modelId,
    positions: options.positions, views, stats,
    onFrame: (sequence) => status.set('streaming', `stream ${options.stream}: frame ${sequence}`),
    onError: (error) => status.fail(error),
  });
  followMethodBoxes(options, (methods) => {
    views.setVisible(methods);
    watch.setMethods(methods);
  });
  status.set('ready', `rest pose: waiting for the frames of stream ${options.stream}`);
  let lastFigures = 0;
  views.renderer.setAnimationLoop((now) => {
    if (views.drawIfNeeded() && watch.drawn() > 0) stats.frameDrawn(now);
    if (now - lastFigures > 250) {
      lastFigures = now;
      status.figures({ ...stats.figures(now), stream: watch.figures() }, views.viewportRects());
    }
  });
}

async function start() {
  const options = readUrlOptions(window.location);
  status.set('connecting', `connecting to ${options.ws}`);
  const connection = await SweepdConnection.open(options.ws, options.token);
  status.set('loading');
  const info = await chooseModel(connection, options.stream ?? options.model);
  const mesh = bodyAs(await connection.request((id) => meshRequest(id, info.modelId())), pb.Mesh);
  const views = new BodyViews(element('canvas'));
  views.setRestMesh(mesh);
  const stats = new StreamStats();
  if (options.positions === 'meshopt') await decoderReady;
  if (options.stream) return watchStream(options, connection, info.modelId(), views, stats);
  const stream = new PoseStream(connection, info.modelId(), options.positions, views, stats,
                                (e) => status.fail(e));
  const player = new ClipPlayer();
  let clipId = null;
  let posing = true;  // the sliders' pose is shown (the rest pose at first), not the clip
  const play = element('play');
  function pause() {
    player.pause(performance.now());
    play.textContent = 'Play';
  }

  const sliderInputs = ['joint-x', 'joint-y', 'joint-z'].map(element);
  const sliders = new JointSliders(element('joint'), sliderInputs, () => {
    posing = true;
    pause();
    status.set('posing', 'posing with the joint sliders');
  });
  sliders.setJoints(jointNames(info), restRotations(info));
  stream.poseAt = (now) => {
    if (posing) {
      const { names, rotations } = sliders.rotations();
      const key = `pose ${names.join()} ${rotations.map((q) => q.toArray().join()).join()}`;
      return { key, request: (id, fields) => poseByName(id, fields, names, rotations) };
    }
    const frame = player.frameAt(now);
    element('frame').value = frame;
    element('frame-label').textContent = `frame ${frame} / ${player.frameCount}`;
    return { key: `clip ${clipId} ${frame}`,
             request: (id, fields) => poseFromClip(id, fields, clipId, frame) };
  };

  play.addEventListener('click', () => {
    if (player.playing) return pause();
    posing = false;
    player.play(performance.now());
    play.textContent = 'Pause';
    status.set('streaming', 'playing the clip');
  });
  element('frame').addEventListener('input', (event) => {
    posing = false;
    player.seek(Number(event.target.value), performance.now());
  });
  element('rest-pose').addEventListener('click', () => sliders.reset());
  followMethodBoxes(options, (methods) => {
    views.setVisible(methods);
    stream.setMethods(methods);
  });
  async function upload(file) {
    status.set('uploading', `uploading ${file.name}`);
    const text = await file.text();
    const scale = Number(element('clip-scale').value);
    const clip = bodyAs(await connection.request((id) => uploadClip(id, file.name, text, scale)),
                        pb.ClipInfo);
    clipId = clip.clipId();
    stats.reset();
    player.load(clip.frameCount(), clip.framesPerSecond());
    Object.assign(element('frame'), { max: clip.frameCount() - 1, value: 0, disabled: false });
    play.disabled = false;
    posing = false;
    play.click();
  }
  element('clip-file').addEventListener('change', (event) => {
    if (event.target.files[0]) upload(event.target.files[0]).catch((error) => status.fail(error));
  });

  status.set('ready', 'rest pose: upload a BVH clip, or turn joints');
  let lastFigures = 0;
  views.renderer.setAnimationLoop((now) => {
    stream.pump();
    if (views.drawIfNeeded() && stream.drawn() > 0) stats.frameDrawn(now);
    if (now - lastFigures > 250) {
      lastFigures = now;
      status.figures(stats.figures(now), views.viewportRects());
    }
  });
}

start().catch((error) => status.fail(error));
