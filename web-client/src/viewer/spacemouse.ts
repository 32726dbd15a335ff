// A 3D mouse (3Dconnexion SpaceMouse, SpaceNavigator, SpacePilot, ...) read
// through WebHID: the parsing of its input reports, as a pure function (no
// DOM: tests/spacemouse.test.mjs runs it in node).
//
// The devices send six signed 16-bit little-endian axes, about ±350 at full
// deflection. Older ones (Logitech-era, vendor 0x046d, and the first
// 3Dconnexion ids) send report 1 with the translation (x, y, z) and report 2
// with the rotation (rx, ry, rz); newer ones (vendor 0x256f: SpaceMouse
// Wireless, Pro, Enterprise, the universal receiver) send all six in report
// 1. Report 3 carries the buttons. WebHID's event.data excludes the report
// id byte.
//
// The device's axes: x right, y towards the back (pushing the cap away is
// -y), z down (pressing the cap is +z); rx tilts forward, ry rolls, rz twists
// clockwise seen from above.

/** USB vendor ids of the devices asked for: 3Dconnexion, and Logitech for the older ones. */
export const SPACEMOUSE_VENDORS = [0x256f, 0x046d] as const;

/** The full deflection of an axis, about: the values are divided by it. */
export const AXIS_RANGE = 350;

export interface SpaceMouseReport {
  /** x, y, z in -1..1 (about), or null when the report has none. */
  translation: [number, number, number] | null;
  rotation: [number, number, number] | null;
  /** The button bits (report 3), or null. */
  buttons: number | null;
}

/** Parses one input report; null for a report of another kind or too short. */
export function parseSpaceMouseReport(reportId: number, data: DataView): SpaceMouseReport | null {
  const axes = (at: number): [number, number, number] => [data.getInt16(at, true) / AXIS_RANGE, data.getInt16(at + 2, true) / AXIS_RANGE, data.getInt16(at + 4, true) / AXIS_RANGE];
  if (reportId === 1 && data.byteLength >= 12) return { translation: axes(0), rotation: axes(6), buttons: null };
  if (reportId === 1 && data.byteLength >= 6) return { translation: axes(0), rotation: null, buttons: null };
  if (reportId === 2 && data.byteLength >= 6) return { translation: null, rotation: axes(0), buttons: null };
  if (reportId === 3 && data.byteLength >= 1) {
    let bits = 0;
    for (let i = 0; i < Math.min(4, data.byteLength); ++i) bits |= data.getUint8(i) << (8 * i);
    return { translation: null, rotation: null, buttons: bits >>> 0 };
  }
  return null;
}

/**
 * The camera motion for the state of the six axes, in the camera's frame,
 * per second at full deflection: pan right and up and move forward (in units
 * of `scale`, the distance to the orbit centre), and orbit about the centre
 * (yaw about the view's up, pitch about its right, in radians). Values under
 * the dead zone count as zero.
 */
export function cameraMotion(
  translation: readonly number[],
  rotation: readonly number[],
  deadZone = 0.03,
): { right: number; up: number; forward: number; yaw: number; pitch: number } {
  const d = (v: number) => (Math.abs(v) < deadZone ? 0 : v);
  return {
    right: d(translation[0]!),
    up: -d(translation[2]!),
    forward: -d(translation[1]!),
    yaw: -d(rotation[2]!) * 1.5,
    pitch: -d(rotation[0]!) * 1.5,
  };
}
