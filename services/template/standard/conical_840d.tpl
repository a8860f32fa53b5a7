# Standard NC code: conical gears (tip and root on a cone of angle delta) on a
# SINUMERIK 840D hobbing machine. As cylindrical, but the axial feed moves X
# with Z along the cone (the model gives each feed move both axes), from the
# X at the large end the unit line names; the clearance is the approached
# face's.
#
# One record per line: module[/scope] [when: ..] [calc: ..] [if: ..] :: output
# (format: src/stdcode.rs; expressions and functions: src/expr.rs; parameters:
# src/params.rs). Lines equal to another class's are that module's similar
# components (`gearcam templates analyze`).
@template conical_840d
@class conical
@dialect sinumerik840d
@version 8

main :: %{program.file}
main :: ;$PATH=/_N_MPF_DIR
main :: ; GEARCAM HOBBING PROGRAM {program.name}
main :: ; JOB {comment(job_id)}
main :: ; PART {comment(part_number)}
main :: ; ORDER QTY={quantity} MATERIAL {comment(gear.material)} QUALITY GRADE {gear.quality}
main :: ; SUBMITTED {comment(submitted)} BY {comment(submitted_by)}
main :: ; CLASS {comment(class)}
main :: ; MACHINE {comment(machine.id)} {comment(machine.name)}
main :: ; TEMPLATE {template.id} VERSION {template.version}
main :: ; CASES {comment(cases)}
main :: ; MODEL {comment(model_version)}
main :: ; GENERATOR {comment(generator)}
main :: ; GEAR MN={nc(gear.module)} Z={gear.teeth} BETA={deg(gear.helix)}{if(helical and has(gear.hand), " " + upper(gear.hand), "")} B={nc(gear.face_width)} DA1={nc(kin.blank_od)}
main :: ; HOB {comment(hob.id)} Z0={hob.starts} DA0={nc(hob.od)} MN0={nc(hob.module)} GAMMA0={deg(hob.lead_angle)} {upper(hob.hand)}
main :: ; CUT {upper(kin.cut_mode)} VC={nc(process.cutting_speed)} FA={nc(process.feed)} H={nc(kin.depth)} L={nc(kin.centre_distance)}
main :: ; TIME {nc(kin.part_time)} MIN PER PART, {kin.cuts} CUT(S)
main :: ;
main :: {N()} G71 G90 G94 DIAMOF ; METRIC, ABSOLUTE, FEED PER MINUTE, X IS THE CENTRE DISTANCE (A RADIUS)
main :: {N()} {machine.work_offset} ; WORK OFFSET: Z0 ON THE TABLE PLANE, X0 ON THE TABLE AXIS
motion :: ; A -> B: RETRACT RADIALLY, UP TO THE START HEIGHT, SWIVEL THE HOB HEAD, THEN APPROACH
motion :: {N()} G0 G90 {ax.radial}={nc(A.x)} ; RADIAL RETRACT FIRST, FROM WHEREVER THE HOB STANDS
motion :: {N()} G0 G90 {ax.axial}={nc(A.z)}
motion :: {N()} G0 G90 {ax.swivel}={deg(first.swivel)} ; HOB HEAD SWIVELLED AT THE START POINT
motion :: {N()} G0 G90 {ax.axial}={nc(first.B.z)}
motion :: {N()} G0 G90 {ax.radial}={nc(first.B.x)}
preparation if: options.outer_support :: {N()} M{mc.outer_support_on} ; OUTER HOB SUPPORT ENGAGE
preparation if: options.fixture_clamp :: {N()} M{mc.fixture_clamp} ; FIXTURE CLAMP
conditions if: options.coolant :: {N()} M{mc.coolant_on} ; COOLANT ON
conditions if: options.chip_conveyor :: {N()} M{mc.chip_conveyor_on} ; CHIP CONVEYOR ON
conditions if: options.mist_separator :: {N()} M{mc.mist_on} ; OIL MIST SEPARATOR ON
motion/unit :: ; CONE DELTA={deg(k.cone.angle)} LARGE END {upper(k.cone.large_end)}: X FOLLOWS Z BY {factor(k.cone.x_per_z)} MM/MM FROM X={nc(k.cone.x_large)} AT THE LARGE END
synchronous/unit :: {N()} {P(1)}={nc(u.module)} ; NORMAL MODULE MN, MM
synchronous/unit :: {N()} {P(2)}={u.teeth} ; NUMBER OF TEETH Z
synchronous/unit :: {N()} {P(3)}={deg(u.helix)} ; HELIX ANGLE BETA, DEG
synchronous/unit :: {N()} {P(4)}={u.hob.starts} ; HOB STARTS Z0
synchronous/unit :: {N()} {P(5)}={deg(u.hob.lead_angle)} ; HOB LEAD ANGLE GAMMA0, DEG
shift/unit if: k.has_shift :: ; HOB SHIFT PER {upper(k.shift.mode)}: {k.shift.positions} POSITIONS FROM {nc(k.shift.start)} TO {nc(k.shift.last)} MM
shift/unit if: k.has_shift :: {N()} {P(20)}={nc(k.shift.start)} ; SHIFT START, MM
shift/unit if: k.has_shift :: {N()} {P(21)}={nc(k.shift.end)} ; SHIFT END, MM
shift/unit if: k.has_shift :: {N()} {P(22)}={nc(k.shift.step)} ; SHIFT PER STEP, MM
shift/unit if: k.has_shift :: {N()} {P(23)}={k.shift.parts_per_step} ; PARTS PER SHIFT STEP
shift/unit if: k.has_shift :: {N()} {P(24)}={k.shift.positions} ; SHIFT POSITIONS
shift/unit if: k.has_shift :: ; {P(25)} COUNTS THE PARTS CUT WITH THIS HOB SETTING; SET {P(25)}=0 AFTER A HOB CHANGE
shift/unit if: k.has_shift :: {N()} IF {P(25)}>={P(23)}*{P(24)} ; EVERY SHIFT POSITION HAS CUT {P(23)} PARTS
shift/unit if: k.has_shift :: {N()} {P(25)}=0 ; START AGAIN AT THE SHIFT START
shift/unit if: k.has_shift :: {N()} ENDIF
shift/unit if: k.has_shift :: {N()} {P(26)}=TRUNC({P(25)}/{P(23)}) ; SHIFT STEPS SO FAR
synchronous/unit calc: lead = if(k.use_z, "," + ax.axial + ",1", "") + if(k.use_y, "," + ax.shift + ",1", ""); factors = if(k.use_z, "," + ax.axial + ",0," + factor(k.c_per_z) + ",1", "") + if(k.use_y, "," + ax.shift + ",0," + factor(k.c_per_y) + ",1", "") :: ; GEARBOX: {ax.table} FOLLOWS {ax.hob} BY Z0/Z{if(k.use_z, ", " + ax.axial + " BY THE DIFFERENTIAL", "")}{if(k.use_y, ", " + ax.shift + " BY THE SHIFT COMPENSATION", "")}, DEG/MM
synchronous/unit :: {N()} EGDEF({ax.table},{ax.hob},1{lead})
synchronous/unit :: {N()} EGONSYNE({ax.table},"FINE",0,"DCT",{ax.hob},0,{k.coupling.num},{k.coupling.den}{factors}) ; COUPLED AT FIXED SYNCHRONISED POSITIONS: EVERY CUT SHARES THIS REFERENCE
conditions/unit :: {N()} M{mc.spindle_on} S={nc(k.hob_rpm)} ; HOB ON, RPM
motion/cut :: ; CUT {cut.number} OF {cut.count} ({upper(k.cut_mode)} CUT): {if(cut.finish, "FINISH", "ROUGH")} TO H={nc(cut.depth)} L={nc(cut.centre_distance)}, {nc(cut.time)} MIN
motion/cut if: cut.resync :: {N()} G0 G90 {ax.radial}={nc(cut.B.x)} ; OUT OF THE GAPS, THE GEARBOX STAYS COUPLED
motion/cut if: cut.resync :: {N()} G0 G90 {ax.axial}={nc(cut.B.z)}
motion/move calc: shift_index = if(k.shift.by_cut, "(" + P(26) + "*" + text(cut.count) + "+" + text(cut.number - 1) + ")", P(26)); words = if(has(m.x), " " + ax.radial + "=" + nc(m.x), "") + if(has(m.z), " " + ax.axial + "=" + nc(m.z), "") + if(has(m.y), " " + ax.shift + "=" + if(k.has_shift, P(20) + "+" + P(22) + "*(" + shift_index + " MOD " + P(24) + ")", nc(m.y)), "") :: ; {comment(m.note)}
motion/move if: m.kind == "rapid" :: {N()} G0 G90{words}
motion/move if: m.kind == "feed" :: {N()} G1 G90 G94{words} F={nc(m.feed)}
motion/move if: m.kind == "arc" :: {N()} CIP{words} I1={nc(m.via.x)} K1={nc(m.via.z)} F={nc(m.feed)}
motion/move if: m.kind == "dwell" :: {N()} G4 F={nc(m.dwell)} ; DWELL, S
conditions/unit :: {N()} M{mc.spindle_off} ; HOB OFF
motion :: ; E -> A: BACK TO THE START POINT
motion :: {N()} G0 G90 {ax.radial}={nc(A.x)} ; RADIAL RETRACT FIRST: THE HOB LEAVES THE BLANK ZONE
motion :: {N()} G0 G90 {ax.axial}={nc(A.z)}
synchronous if: options.sync_cancel :: {N()} EGOFS({ax.table}) ; GEARBOX OFF
synchronous if: options.sync_cancel :: {N()} EGDEL({ax.table}) ; GEARBOX DEFINITION DELETED
shift if: any_shift :: {N()} {P(25)}={P(25)}+1 ; PARTS CUT WITH THIS HOB SETTING
conditions if: options.coolant :: {N()} M{mc.coolant_off} ; COOLANT OFF
conditions if: options.chip_conveyor :: {N()} M{mc.chip_conveyor_off} ; CHIP CONVEYOR OFF
conditions if: options.mist_separator :: {N()} M{mc.mist_off} ; OIL MIST SEPARATOR OFF
preparation if: options.outer_support :: {N()} M{mc.outer_support_off} ; OUTER HOB SUPPORT RELEASE
preparation if: options.fixture_clamp :: {N()} M{mc.fixture_unclamp} ; FIXTURE UNCLAMP
main :: {N()} M{mc.program_end} ; END OF PROGRAM
