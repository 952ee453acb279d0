"""The Bladed-style swap array (``avrSWAP``) of ``DISCON`` controllers: the record map.

A ``DISCON(avrSWAP, aviFAIL, accINFILE, avcOUTNAME, avcMSG)`` library exchanges
everything through one single-precision array whose records (1-based, as in the
Bladed manual and OpenFAST's ServoDyn) have fixed meanings.  This module is the
map we implemented, following what OpenFAST ServoDyn sends and reads (its
``BladedInterface`` module) and what ROSCO 2.10.6 reads (``ReadAvrSWAP``):

**Status** (record 1): 0 first call (initialization, at the first time), 1 every
later step, −1 final call (ROSCO then only cleans up).

**Inputs** written before each call: :data:`MEASUREMENT_RECORDS` (measured signals
by name, SI units) and :data:`CONSTANT_RECORDS` (interface constants and the
ServoDyn parameters of records 5-9, 13, 16-19, 22, 26, 28).  Records 35 and 36
(generator contactor, shaft brake) send back what the library returned at the
previous call (initially 1 and 0), as ServoDyn does.  Record 11 sends the
previous pitch demand of blade 1.  String lengths: record 49 (message buffer
size), 50 (length of the input-file name + 1), 51 (length of the run name + 1),
64 (size of the ``avcOUTNAME`` buffer).  Record 129 is the array size.

**Outputs** read after each call: :data:`COMMAND_RECORDS` — individual pitch
demands 42-44 (or the collective demand 45 when record 28 is 0), generator torque
demand 47, yaw rate demand 48, generator contactor 35, brake flag 36, and the
override flags 55, 56 (which must stay 0).

The extended interface of OpenFAST ≥ 3.5 (records 1001-1018: platform motions,
read by ROSCO when ``Ext_Interface = 1``, by the exported floating NMPC always): the
platform's displacements 1001-1006 (``PtfmSurge`` … ``PtfmYaw``, SI) from a plant that
has them, as OpenFAST v5 fills them for every library; its velocities and accelerations
(1007-1018) stay zero, and a single-point lidar's records 2001… are written when the
caller has one (:func:`mbsym.wind.inflow.lidar_records`); the array is allocated with
:data:`SWAP_SIZE` records so such a library never reads past its end.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SWAP_SIZE", "MEASUREMENT_RECORDS", "CONSTANT_RECORDS", "COMMAND_RECORDS", "MEASUREMENT_UNITS",
           "COMMAND_UNITS", "TORQUE_TABLE_START", "LOGGING_CHANNELS"]

#: Number of float32 records allocated (covers OpenFAST's extended interface, records up to 3300).
SWAP_SIZE = 3300
#: Start of the torque-speed look-up table (Bladed ≥ 4.3; OpenFAST's ``R``).
TORQUE_TABLE_START = 165
#: Maximum number of logging channels announced to the library (record 62).
LOGGING_CHANNELS = 300

#: Measurement name → (1-based record(s), unit, meaning).  Names follow OpenFAST channels, units are SI.
MEASUREMENT_RECORDS: dict[str, tuple[int, str, str]] = {
    "BldPitch1": (4, "rad", "blade 1 pitch angle"),
    "RotPwr": (14, "W", "measured shaft (rotor) power"),
    "GenPwr": (15, "W", "measured electrical power"),
    "GenSpeed": (20, "rad/s", "measured generator (HSS) speed"),
    "RotSpeed": (21, "rad/s", "measured rotor (LSS) speed"),
    "GenTq": (23, "N m", "measured generator torque"),
    "YawErr": (24, "rad", "measured yaw error (nacelle vane)"),
    "Wind1VelX": (27, "m/s", "hub-height wind speed"),
    "RootMyc1": (30, "N m", "blade 1 root out-of-plane moment"),
    "RootMyc2": (31, "N m", "blade 2 root out-of-plane moment"),
    "RootMyc3": (32, "N m", "blade 3 root out-of-plane moment"),
    "BldPitch2": (33, "rad", "blade 2 pitch angle"),
    "BldPitch3": (34, "rad", "blade 3 pitch angle"),
    "NacYaw": (37, "rad", "nacelle yaw angle (record 37 = NacYaw - NacYaw_North)"),
    "YawBrTAxp": (53, "m/s^2", "tower-top fore-aft acceleration"),
    "YawBrTAyp": (54, "m/s^2", "tower-top side-side acceleration"),
    "Azimuth": (60, "rad", "rotor azimuth angle"),
    "RootMxc1": (69, "N m", "blade 1 root in-plane moment"),
    "RootMxc2": (70, "N m", "blade 2 root in-plane moment"),
    "RootMxc3": (71, "N m", "blade 3 root in-plane moment"),
    "LSSTipMya": (73, "N m", "rotating hub My"),
    "LSSTipMza": (74, "N m", "rotating hub Mz"),
    "LSSTipMys": (75, "N m", "fixed hub My"),
    "LSSTipMzs": (76, "N m", "fixed hub Mz"),
    "YawBrMyn": (77, "N m", "yaw bearing My"),
    "YawBrMzn": (78, "N m", "yaw bearing Mz"),
    "NcIMURAxs": (82, "rad/s^2", "nacelle roll acceleration"),
    "NcIMURAys": (83, "rad/s^2", "nacelle nodding acceleration"),
    "NcIMURAzs": (84, "rad/s^2", "nacelle yaw acceleration"),
    "LSSTipMxa": (109, "N m", "shaft torque"),
    "LSShftFxa": (110, "N", "rotor thrust (rotating LSS force x)"),
    "LSShftFys": (111, "N", "non-rotating LSS force y"),
    "LSShftFzs": (112, "N", "non-rotating LSS force z"),
    # OpenFAST's extended interface (BladedInterface_EX.f90): the platform's displacements
    "PtfmSurge": (1001, "m", "platform surge (extended record TDX)"),
    "PtfmSway": (1002, "m", "platform sway (extended record TDY)"),
    "PtfmHeave": (1003, "m", "platform heave (extended record TDZ)"),
    "PtfmRoll": (1004, "rad", "platform roll (extended record RDX, small angle)"),
    "PtfmPitch": (1005, "rad", "platform pitch (extended record RDY, small angle)"),
    "PtfmYaw": (1006, "rad", "platform yaw (extended record RDZ, small angle)"),
}
MEASUREMENT_UNITS = {name: unit for name, (_, unit, _) in MEASUREMENT_RECORDS.items()}

#: Constant inputs: name → (record, unit, meaning).  Values come from ServoDyn (or defaults 0).
CONSTANT_RECORDS: dict[str, tuple[int, str, str]] = {
    "pitch_setpoint": (5, "rad", "below-rated pitch set-point (Ptch_SetPnt)"),
    "pitch_min": (6, "rad", "minimum pitch (Ptch_Min)"),
    "pitch_max": (7, "rad", "maximum pitch (Ptch_Max)"),
    "pitch_rate_min": (8, "rad/s", "minimum pitch rate (PtchRate_Min)"),
    "pitch_rate_max": (9, "rad/s", "maximum pitch rate (PtchRate_Max)"),
    "demanded_power": (13, "W", "demanded power (GenPwr_Dem)"),
    "optimal_mode_gain": (16, "N m/(rad/s)^2", "optimal mode gain (Gain_OM)"),
    "optimal_mode_min_speed": (17, "rad/s", "minimum generator speed (GenSpd_MinOM)"),
    "optimal_mode_max_speed": (18, "rad/s", "optimal mode maximum speed (GenSpd_MaxOM)"),
    "demanded_speed": (19, "rad/s", "demanded generator speed above rated (GenSpd_Dem)"),
    "demanded_torque": (22, "N m", "demanded generator torque above rated (GenTrq_Dem)"),
    "air_density": (95, "kg/m^3", "air density (ServoDyn customization)"),
    "average_wind_speed": (96, "m/s", "average wind speed (ServoDyn customization)"),
}

#: Command name → (record, unit, meaning) read back after each call.
COMMAND_RECORDS: dict[str, tuple[int, str, str]] = {
    "BlPitchCom1": (42, "rad", "demanded pitch, blade 1 (record 45 if collective)"),
    "BlPitchCom2": (43, "rad", "demanded pitch, blade 2 (record 45 if collective)"),
    "BlPitchCom3": (44, "rad", "demanded pitch, blade 3 (record 45 if collective)"),
    "GenTqCom": (47, "N m", "demanded generator torque"),
    "YawRateCom": (48, "rad/s", "demanded nacelle yaw rate"),
    "GenState": (35, "-", "generator contactor (0 off, 1 main)"),
    "BrakeStatus": (36, "-", "shaft brake flag (0 off, 1 on, 16 torque from record 107)"),
}
COMMAND_UNITS = {name: unit for name, (_, unit, _) in COMMAND_RECORDS.items()}
COLLECTIVE_PITCH_RECORD = 45


def fill_constants(swap: np.ndarray, *, dt: float, n_blades: int, individual_pitch: bool,
                   infile_length: int, outname_length: int, outname_buffer: int, message_buffer: int,
                   constants: dict[str, float], torque_table: tuple[np.ndarray, np.ndarray]) -> None:
    """Write the records that do not change from call to call (1-based record numbers)."""
    speeds, torques = torque_table
    rec = {3: dt, 10: 0.0, 12: 0.0, 26: float(len(speeds)), 28: float(individual_pitch), 29: 0.0,
           49: float(message_buffer), 50: float(infile_length + 1), 51: float(outname_length + 1),
           61: float(n_blades), 62: float(LOGGING_CHANNELS),
           63: float(TORQUE_TABLE_START + 2 * len(speeds)), 64: float(outname_buffer), 66: 1001.0,
           98: 0.0, 117: 0.0, 129: float(swap.size),
           25: float(TORQUE_TABLE_START) if len(speeds) else 0.0}
    for name, (record, _, _) in CONSTANT_RECORDS.items():
        rec[record] = float(constants.get(name, 0.0))
    for record, value in rec.items():
        swap[record - 1] = value
    for i, (w, q) in enumerate(zip(speeds, torques)):
        swap[TORQUE_TABLE_START - 1 + 2 * i] = w
        swap[TORQUE_TABLE_START + 2 * i] = q
