// @armature/client: the Armature server from TypeScript over gRPC-Web.
export * from './client.js';
export * from './errors.js';
export * from './sessions.js';
export * from './crowd_decoder.js';
export * from './crowd_session.js';
export * from './import_asset.js';
export { SessionLog } from './session_log.js';
export { WorkerWebSocket } from './worker_socket.js';
export { packFloats } from './arrays.js';
export { Space, Interpolation, WrapMode } from './gen/armature/v1/types_pb.js';
export { SkinningMethod } from './gen/armature/v1/meshes_pb.js';
export { PoseService } from './gen/armature/v1/poses_pb.js';
export { MeshService } from './gen/armature/v1/meshes_pb.js';
export { AssetService } from './gen/armature/v1/assets_pb.js';
export { IkService } from './gen/armature/v1/ik_pb.js';
export { DeformService } from './gen/armature/v1/deform_pb.js';
export { AuthoringService } from './gen/armature/v1/authoring_pb.js';
export { CrowdService } from './gen/armature/v1/crowd_pb.js';
