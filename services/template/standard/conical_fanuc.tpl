# Standard NC code: conical gears (tip and root on a cone of angle delta) on a
# FANUC EGB hobbing machine. The axial feed moves X with Z along the cone (the
# model gives each feed move both axes), from the X at the large end the unit
# line names; the clearance is the approached face's.
#
# FANUC EGB dialect as in cylindrical_fanuc.tpl (read its header). One record
# per line: module[/scope] [when: ..] [calc: ..] [if: ..] :: output (format:
# src/stdcode.rs; expressions: src/expr.rs; parameters: src/params.rs). Lines
# equal to another class's are that module's similar components.
@template conical_fanuc
@class conical
@dialect fanuc
@version 6

main :: %
main :: {program.name} ({upper(comment(part_number))} HOBBING)
main :: (GEARCAM HOBBING PROGRAM {program.name})
main :: (JOB {upper(comment(job_id))})
main :: (PART {upper(comment(part_number))})
main :: (ORDER QTY={quantity} MATERIAL {upper(comment(gear.material))} QUALITY GRADE {gear.quality})
main :: (SUBMITTED {upper(comment(submitted))} BY {upper(comment(submitted_by))})
main :: (CLASS {upper(comment(class))})
main :: (MACHINE {upper(comment(machine.id))} {upper(comment(machine.name))})
main :: (TEMPLATE {upper(template.id)} VERSION {template.version})
main :: (CASES {upper(comment(cases))})
main :: (MODEL {upper(comment(model_version))})
main :: (GENERATOR {upper(comment(generator))})
main :: (GEAR MN={nc(gear.module)} Z={gear.teeth} BETA={deg(gear.helix)}{if(helical and has(gear.hand), " " + upper(gear.hand), "")} B={nc(gear.face_width)} DA1={nc(kin.blank_od)})
main :: (HOB {upper(comment(hob.id))} Z0={hob.starts} DA0={nc(hob.od)} MN0={nc(hob.module)} GAMMA0={deg(hob.lead_angle)} {upper(hob.hand)})
main :: (CUT {upper(kin.cut_mode)} VC={nc(process.cutting_speed)} FA={nc(process.feed)} H={nc(kin.depth)} L={nc(kin.centre_distance)})
main :: (TIME {nc(kin.part_time)} MIN PER PART, {kin.cuts} CUT[S])
main :: {N()} G21 (METRIC INPUT)
main :: {N()} G90 G94 G18 {machine.work_offset} (ABSOLUTE, FEED PER MINUTE IN G-CODE SYSTEM {upper(machine.gcode_system)}, ARCS IN THE Z-X PLANE, WORK OFFSET: Z0 ON THE TABLE PLANE, X0 ON THE TABLE AXIS)
motion :: (A TO B: RETRACT RADIALLY, UP TO THE START HEIGHT, SWIVEL THE HOB HEAD, THEN APPROACH)
motion :: {N()} G00 G90 {ax.radial}{nc(A.x)} (RADIAL RETRACT FIRST, FROM WHEREVER THE HOB STANDS)
motion :: {N()} G00 G90 {ax.axial}{nc(A.z)}
motion :: {N()} G00 G90 {ax.swivel}{deg(first.swivel)} (HOB HEAD SWIVELLED AT THE START POINT)
motion :: {N()} G00 G90 {ax.axial}{nc(first.B.z)}
motion :: {N()} G00 G90 {ax.radial}{nc(first.B.x)}
preparation if: options.outer_support :: {N()} M{mc.outer_support_on} (OUTER HOB SUPPORT ENGAGE)
preparation if: options.fixture_clamp :: {N()} M{mc.fixture_clamp} (FIXTURE CLAMP)
conditions if: options.coolant :: {N()} M{mc.coolant_on} (COOLANT ON)
conditions if: options.chip_conveyor :: {N()} M{mc.chip_conveyor_on} (CHIP CONVEYOR ON)
conditions if: options.mist_separator :: {N()} M{mc.mist_on} (OIL MIST SEPARATOR ON)
motion/unit :: (CONE DELTA={deg(k.cone.angle)} LARGE END {upper(k.cone.large_end)}: X FOLLOWS Z BY {factor(k.cone.x_per_z)} MM/MM FROM X={nc(k.cone.x_large)} AT THE LARGE END)
synchronous/unit :: {P(1)}={nc(u.module)} (NORMAL MODULE MN, MM)
synchronous/unit :: {P(2)}={u.teeth} (NUMBER OF TEETH Z)
synchronous/unit :: {P(3)}={deg(u.helix)} (HELIX ANGLE BETA, DEG)
synchronous/unit :: {P(4)}={u.hob.starts} (HOB STARTS Z0)
synchronous/unit :: {P(5)}={deg(u.hob.lead_angle)} (HOB LEAD ANGLE GAMMA0, DEG)
shift/unit if: k.has_shift :: (HOB SHIFT PER {upper(k.shift.mode)}: {k.shift.positions} POSITIONS FROM {nc(k.shift.start)} TO {nc(k.shift.last)} MM)
shift/unit if: k.has_shift :: {P(20)}={nc(k.shift.start)} (SHIFT START, MM)
shift/unit if: k.has_shift :: {P(21)}={nc(k.shift.end)} (SHIFT END, MM)
shift/unit if: k.has_shift :: {P(22)}={nc(k.shift.step)} (SHIFT PER STEP, MM)
shift/unit if: k.has_shift :: {P(23)}={k.shift.parts_per_step} (PARTS PER SHIFT STEP)
shift/unit if: k.has_shift :: {P(24)}={k.shift.positions} (SHIFT POSITIONS)
shift/unit if: k.has_shift :: ({P(25)} COUNTS THE PARTS CUT WITH THIS HOB SETTING, SET {P(25)}=0 AFTER A HOB CHANGE)
shift/unit if: k.has_shift :: IF [{P(25)} GE {P(23)}*{P(24)}] THEN {P(25)}=0 (EVERY SHIFT POSITION HAS CUT {P(23)} PARTS: START AGAIN)
shift/unit if: k.has_shift :: {P(26)}=FIX[{P(25)}/{P(23)}] (SHIFT STEPS SO FAR)
shift/unit when: k.has_shift calc: first_index = if(k.shift.by_cut, "[" + P(26) + "*" + text(k.cuts) + "]", P(26)) if: k.has_shift :: {P(27)}={first_index}-FIX[{first_index}/{P(24)}]*{P(24)} (SHIFT POSITION OF THE FIRST CUT)
shift/unit if: k.has_shift :: {P(28)}={P(20)}+{P(22)}*{P(27)} (SHIFT AXIS POSITION, MM)
shift/unit if: k.has_shift :: {N()} G00 G90 {ax.shift}[{P(28)}] (HOB SHIFTED BEFORE COUPLING)
shift/unit calc: ylast = k.y0 if: k.tangential :: {N()} G00 G90 {ax.shift}{nc(k.y0)} (HOB SHIFTED TO THE TANGENTIAL START BEFORE COUPLING)
synchronous/unit calc: direction = if(k.coupling.num < 0, -1, 1); helix_p = if(k.c_per_z < 0, -abs(u.helix), abs(u.helix)) :: ({ax.table} FOLLOWS THE HOB BY Z0/Z{if(k.use_z, ", HELICAL COMPENSATION FROM Q AND P", "")}{if(k.use_y, ", " + ax.shift + " MOVES WITH THEIR " + ax.table + " CORRECTION " + factor(k.c_per_y) + " DEG/MM", "")})
synchronous/unit :: {N()} G81 T{u.teeth} L{direction * u.hob.starts}{if(k.use_z, " Q" + nc(u.module) + " P" + deg(helix_p), "")} (EGB ON)
conditions/unit :: {N()} M{mc.spindle_on} S{int(k.hob_rpm)} (HOB ON, RPM)
motion/cut :: (CUT {cut.number} OF {cut.count} [{upper(k.cut_mode)} CUT]: {if(cut.finish, "FINISH", "ROUGH")} TO H={nc(cut.depth)} L={nc(cut.centre_distance)}, {nc(cut.time)} MIN)
motion/cut if: cut.resync :: {N()} G00 G90 {ax.radial}{nc(cut.B.x)} (OUT OF THE GAPS, GEARBOX STAYS COUPLED)
motion/cut if: cut.resync :: {N()} G00 G90 {ax.axial}{nc(cut.B.z)}
motion/move calc: words = if(has(m.x), " " + ax.radial + nc(m.x), "") + if(has(m.z), " " + ax.axial + nc(m.z), "") :: ({comment(m.note)})
shift/move if: has(m.y) and k.shift.by_cut :: {P(27)}=[{P(26)}*{cut.count}+{cut.number - 1}]-FIX[[{P(26)}*{cut.count}+{cut.number - 1}]/{P(24)}]*{P(24)} (SHIFT POSITION OF THIS CUT)
shift/move if: has(m.y) and k.shift.by_cut :: {P(29)}={P(20)}+{P(22)}*{P(27)}-{P(28)} (SHIFT, MM)
shift/move if: has(m.y) and k.shift.by_cut :: {N()} G01 G91 {ax.shift}[{P(29)}] {ax.table}[{P(29)}*{factor(k.c_per_y)}] F{nc(machine.max_feed)}
shift/move if: has(m.y) and k.shift.by_cut :: {P(28)}={P(28)}+{P(29)}
shift/move when: has(m.y) and not k.has_shift calc: dy = m.y - ylast; ylast = m.y if: has(m.y) and not k.has_shift and dy != 0 :: {N()} G01 G91 {ax.shift}{nc(dy)} {ax.table}{deg(dy * k.c_per_y)} F{nc(if(m.kind == "feed", m.feed, machine.max_feed))}
motion/move if: m.kind == "rapid" and words != "" :: {N()} G00 G90{words}
motion/move if: m.kind == "feed" and words != "" :: {N()} G01 G90 G94{words} F{nc(m.feed)}
motion/move if: m.kind == "dwell" :: {N()} G04 X{nc(m.dwell)} (DWELL, S)
conditions/unit :: {N()} M{mc.spindle_off} (HOB OFF)
motion :: (E TO A: BACK TO THE START POINT)
motion :: {N()} G00 G90 {ax.radial}{nc(A.x)} (RADIAL RETRACT FIRST: THE HOB LEAVES THE BLANK ZONE)
motion :: {N()} G00 G90 {ax.axial}{nc(A.z)}
synchronous if: options.sync_cancel :: {N()} G80 (EGB OFF)
shift if: any_shift :: {P(25)}={P(25)}+1 (PARTS CUT WITH THIS HOB SETTING)
conditions if: options.coolant :: {N()} M{mc.coolant_off} (COOLANT OFF)
conditions if: options.chip_conveyor :: {N()} M{mc.chip_conveyor_off} (CHIP CONVEYOR OFF)
conditions if: options.mist_separator :: {N()} M{mc.mist_off} (OIL MIST SEPARATOR OFF)
preparation if: options.outer_support :: {N()} M{mc.outer_support_off} (OUTER HOB SUPPORT RELEASE)
preparation if: options.fixture_clamp :: {N()} M{mc.fixture_unclamp} (FIXTURE UNCLAMP)
main :: {N()} M{mc.program_end} (END OF PROGRAM)
main :: %
