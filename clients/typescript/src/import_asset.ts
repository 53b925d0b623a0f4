// Importing a file: ImportAsset is client-streaming, which gRPC-Web over
// fetch cannot carry, so the file goes as the raw body of REST's
// POST /v1/assets:import (the gateway streams it to ImportAsset chunk by
// chunk) with the first message's fields in the query, as `armature import`
// sends them; the answer is the ImportAssetResponse.
import { fromJson } from '@bufbuild/protobuf';
import type { JsonValue } from '@bufbuild/protobuf';

import { ArmatureError, Code, errorForStatus } from './errors.js';
import { ImportAssetResponseSchema } from './gen/armature/v1/assets_pb.js';
import type { ImportAssetResponse } from './gen/armature/v1/assets_pb.js';

export interface ImportAssetOptions {
  /** The file's name: its extension gives the format. */
  filename: string;
  /** The asset's name; default: the filename's stem. */
  name?: string;
  /** bvh, gltf, glb, obj or fbx; default: from the filename or the content. */
  format?: string;
  /** Replaces an asset of the same name instead of AlreadyExistsError. */
  replace?: boolean;
  /**
   * How closely the server's runtime form of each clip keeps the stored one
   * (ImportAssetRequest.precision): "exact" (the stored keys bit for bit) or
   * a bound in centimetres, in (0, 10]; absent: the server's --clip-error.
   */
  precision?: 'exact' | number;
  signal?: AbortSignal;
}

/** The query's value of a precision: "exact" or the centimetres as the shortest decimal that reads back. */
export function precisionParam(precision: 'exact' | number): string {
  if (precision === 'exact') return precision;
  if (typeof precision !== 'number' || !Number.isFinite(precision)) {
    throw new TypeError(`precision ${String(precision)} is neither "exact" nor a number of centimetres`);
  }
  return String(precision);
}

/** Imports `data` into the server at `baseUrl`; rejects with the ArmatureError of a refusal. */
export async function importAsset(baseUrl: string, data: Uint8Array | ArrayBuffer | Blob, options: ImportAssetOptions,
                                  transport: { token?: string; fetch?: typeof globalThis.fetch } = {}):
    Promise<ImportAssetResponse> {
  const query = new URLSearchParams({ filename: options.filename });
  if (options.name !== undefined) query.set('name', options.name);
  if (options.format !== undefined) query.set('format', options.format);
  if (options.replace) query.set('replace', 'true');
  if (options.precision !== undefined) query.set('precision', precisionParam(options.precision));
  const headers: Record<string, string> = { 'Content-Type': 'application/octet-stream' };
  if (transport.token !== undefined) headers.Authorization = `Bearer ${transport.token}`;
  const fetch = transport.fetch ?? globalThis.fetch;
  const url = `${baseUrl.replace(/\/+$/, '')}/v1/assets:import?${query}`;
  let res: Response;
  try {
    res = await fetch(url, { method: 'POST', headers, body: data as BodyInit, signal: options.signal });
  } catch (e) {
    throw new ArmatureError(Code.Unavailable, `could not import ${options.filename}: ${String(e)}`);
  }
  const body = (await res.json().catch(() => ({}))) as { code?: Code; message?: string };
  if (!res.ok) throw errorForStatus(body.code ?? Code.Unknown, body.message ?? `HTTP ${res.status}`);
  return fromJson(ImportAssetResponseSchema, body as JsonValue, { ignoreUnknownFields: true });
}
