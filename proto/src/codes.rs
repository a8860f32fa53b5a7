//! The catalogue of every error, warning and path-check code gearcam raises,
//! one entry per code: the code, the stages that raise it, what it means and what
//! the user should do.
//!
//! Each code is a variant of [`Code`] (e.g. [`Code::BASE_PITCH_MISMATCH`]), so
//! the compiler checks every code the services raise: a [`crate::JobError`], a
//! [`crate::Warning`] and a [`crate::PathFinding`] carry a [`Code`], never a
//! free string. On the wire a code is its name as text, so readers in other
//! languages see the same strings; [`Code::parse`] reads one back and
//! [`lookup`] finds a code's entry by its text.
//!
//! `docs/errors.md` is generated from [`CATALOGUE`], and the test
//! `cargo test -p gearcam-tests --test error_codes` fails when a code string
//! is written outside this file, when an entry here is raised nowhere, or when
//! the page differs from the catalogue (rewrite it with `GEARCAM_BLESS=1`).
//!
//! Stages: `station`, `knowledge`, `model`, `template`, `agent` (the
//! [`crate::Stage`] the error carries), or `any` for the codec's codes, which
//! every stage that decodes a message can raise. The rules of the NC path
//! check (stage `template (path check)`) are not errors themselves: each
//! finding reaches the user as a `PATH_CHECK_FAILED` error whose `expected`
//! names the rule, and `gearcam check` lists them.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// One code of the catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CodeInfo {
    /// The code.
    pub code: Code,
    /// The stages that raise it, e.g. `model` or `station, knowledge`; a
    /// note in brackets says more (e.g. `model (warning)`).
    pub stage: &'static str,
    /// What it means: one or two plain sentences.
    pub meaning: &'static str,
    /// What the user should do.
    pub action: &'static str,
}

/// The entry of the code whose text is `code`, if the catalogue has it.
pub fn lookup(code: &str) -> Option<&'static CodeInfo> {
    CATALOGUE
        .binary_search_by(|c| c.code.as_str().cmp(code))
        .ok()
        .map(|i| &CATALOGUE[i])
}

/// Declares [`Code`] with one variant per code (documented with its meaning),
/// its text, and [`CATALOGUE`], in the order given (sorted by code).
macro_rules! catalogue {
    ($($code:ident: $stage:literal, $meaning:literal, $action:literal;)*) => {
        /// A code of the catalogue: an error, a warning or a path-check rule.
        /// The variants keep the codes' wire spelling (UPPER_SNAKE) so that
        /// the code in the source is the code the user reads.
        #[allow(non_camel_case_types)]
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Code {
            $(
                #[doc = $meaning]
                $code,
            )*
        }

        impl Code {
            /// The code as text, e.g. `"BASE_PITCH_MISMATCH"`.
            pub const fn as_str(self) -> &'static str {
                match self {
                    $(Code::$code => stringify!($code),)*
                }
            }
        }

        /// Every code gearcam raises, sorted by code.
        pub const CATALOGUE: &[CodeInfo] = &[
            $(CodeInfo {
                code: Code::$code,
                stage: $stage,
                meaning: $meaning,
                action: $action,
            },)*
        ];
    };
}

impl Code {
    /// The code whose text is `text`, if the catalogue has it.
    pub fn parse(text: &str) -> Option<Code> {
        lookup(text).map(|c| c.code)
    }

    /// The code's catalogue entry.
    pub fn info(self) -> &'static CodeInfo {
        // The catalogue lists the variants in declaration order.
        &CATALOGUE[self as usize]
    }

    /// What the code means.
    pub fn meaning(self) -> &'static str {
        self.info().meaning
    }

    /// What the user should do.
    pub fn action(self) -> &'static str {
        self.info().action
    }
}

impl std::fmt::Display for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl AsRef<str> for Code {
    fn as_ref(&self) -> &str {
        self.as_str()
    }
}

impl PartialEq<str> for Code {
    fn eq(&self, other: &str) -> bool {
        self.as_str() == other
    }
}

impl PartialEq<&str> for Code {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

impl PartialEq<String> for Code {
    fn eq(&self, other: &String) -> bool {
        self.as_str() == other
    }
}

impl PartialEq<Code> for &str {
    fn eq(&self, other: &Code) -> bool {
        *self == other.as_str()
    }
}

impl Serialize for Code {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for Code {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Code, D::Error> {
        let text = std::borrow::Cow::<'de, str>::deserialize(d)?;
        Code::parse(&text).ok_or_else(|| {
            serde::de::Error::custom(format!(
                "unknown code {text:?}: this reader knows the codes of its catalogue"
            ))
        })
    }
}

catalogue! {
    ADDENDUM_RANGE: "model",
        "The gear's addendum coefficient ha* is not a positive number.",
        "Correct `gear.addendum_coef` (usually 1).";
    AGENT_OFFLINE: "agent (`gearcam program`)",
        "No agent of the machine named answers on the bus: the machine is not one of the knowledge base's, or its agent does not run. expected lists the machines whose agents are there.",
        "Check the machine id (`gearcam kb list machines`, `mill-machines`, `wire-machines`) and start its agent.";
    ARC_FIT: "model",
        "No tangent-continuous arc spline of the allowed number of arcs holds the flank's or the fillet's tolerance.",
        "Loosen the tolerance the field names (`[die]` flank_tolerance_um or fillet_tolerance_um).";
    AXIAL_FEED_LIMIT: "model",
        "The computed axial feed of the job or of a rough cut is above the machine's feed limit.",
        "Lower `process.feed_mm_per_rev` or the cutting speed.";
    BAD_ARGUMENT: "knowledge (`gearcam kb`)",
        "A `--set` argument of `gearcam kb` is not of the form FIELD=VALUE.",
        "Write each `--set` as field=value, e.g. `--set module_mm=3`.";
    BAD_CANCEL_REQUEST: "station",
        "A cancellation's key does not name who cancels usably: the user chunk of `gearcam/v1/station/cancel/{user}/{job}` must be 1 to 64 characters on one line.",
        "Cancel as a user with a login name (on a plain network `--by NAME`; on a secure one the configuration's login).";
    BAD_HOB_ID: "any",
        "A hob id breaks the id rule (1 to 32 characters from A-Z a-z 0-9 _ -, starting with a letter or digit); got is the id.",
        "Use a hob id that follows the rule.";
    BAD_JOB_ID: "station, agent",
        "A job id in a key or message breaks the id rule (1 to 64 characters from A-Z a-z 0-9 _ -, starting with a letter or digit); got is the id.",
        "Use a job id that follows the rule, or leave `[job] id` out to get a generated one.";
    BAD_JSON: "knowledge (`gearcam kb add`)",
        "The `--from-json` file of `gearcam kb add` is not a JSON object of the record's fields.",
        "Fix the file; `gearcam kb show LIBRARY ID --json` prints a record in this form.";
    BAD_KEY: "knowledge, station",
        "A query used a key of no form its service answers: a knowledge-base key that is not `gearcam/v1/kb/{library}[/{id}]` or `gearcam/v1/kb-changes/{user}/{library}[/{id}]`, or a station submit or cancel key without the user who asks (`gearcam/v1/station/submit/{user}`, `gearcam/v1/station/cancel/{user}/{job}`).",
        "Query the form `expected` names; the user chunk is the name the change is recorded under.";
    BAD_MACHINE_ID: "station",
        "The job's machine id (`spec.job.machine`) breaks the id rule (1 to 32 characters from A-Z a-z 0-9 _ -, starting with a letter or digit).",
        "Name the machine by its id in the knowledge base, e.g. H01.";
    BAD_PROGRAM_NAME: "agent",
        "The program name breaks the controller's naming rule, so the agent does not store it.",
        "Check the part number the name is made from; the error states the rule.";
    BAD_STORE_REQUEST: "agent",
        "A store query has a key or payload the program store does not understand (an unknown key, a version that is not a number, or a change without a store_request payload).",
        "Use the store keys and payloads of proto/README.md, or the `gearcam program` commands.";
    BALL_DIAMETER_RANGE: "model",
        "The ball diameter for the measurement over balls is not positive, or too small to rest on the involute flanks.",
        "Correct `gear.ball_diameter_mm` (about 1.7 times the module) or leave it out.";
    BASE_PITCH_MISMATCH: "model",
        "Hob and gear have different normal base pitches (mn0·cos α0 ≠ mn·cos αn), so the hob cannot generate this gear.",
        "Choose a hob with the gear's module and pressure angle.";
    BLANK_OD_EDGE: "model (warning)",
        "Warning: the blank outside diameter lies near the edge of its allowed window around the tip diameter.",
        "Check the blank before cutting; the job goes on.";
    BLANK_OD_WINDOW: "model",
        "The blank outside diameter lies outside the machine's window around the gear's tip diameter.",
        "Turn the blank to size or correct `gear.blank_od_mm`.";
    BLOCK_COUNT: "template, agent (spiral replay)",
        "Spiral verification finding: a replayed pass has another number of blocks along the spiral than the model.",
        "The program was not sent; report it, the generator is at fault.";
    CENTRE_DISTANCE_TOO_SMALL: "model",
        "The final centre distance is below the theoretical one, so the teeth would be cut thin.",
        "Reduce `process.depth_mm`, or leave it out to use the theoretical depth.";
    CHORD_TOLERANCE_RANGE: "model",
        "The chord tolerance of a parabolic crowning is not positive, or so fine that it needs too many chords.",
        "Correct `gear.crowning.chord_tolerance_mm`.";
    CLASS_AMBIGUOUS: "model",
        "The gear carries the markers of more than one class (cone, crowning, worm wheel, curved tooth).",
        "Keep only the one `[gear.*]` table that describes the gear.";
    CLASS_NOT_PROGRAMMABLE: "model",
        "The gear is a curved-tooth gear: gearcam classifies it but cannot program it yet.",
        "Program this part by hand for now.";
    CLASS_OPTION_UNSUPPORTED: "model",
        "The job asks for an option its gear class does not support (radial-axial infeed on a gear that is not cylindrical, or hob shifting with tangential worm-wheel infeed).",
        "Leave `process.infeed` or `[process.shift]` out, as the message says.";
    CLEARANCE_COEF_RANGE: "model",
        "The tip clearance coefficient c* is negative or not a number.",
        "Correct `gear.clearance_coef` (usually 0.25).";
    CONE_ANGLE_RANGE: "model",
        "The cone angle is outside (0°, 45°), or so large that the root cone reaches the axis within the face width.",
        "Correct `gear.cone.angle_deg` or `gear.face_width_mm`.";
    CONFIRM_FAMILY: "knowledge",
        "A wire EDM job was confirmed; the wire family keeps no cases yet (its technology comes from the wire-data library).",
        "Tune the technology with `gearcam kb edit wire-data` instead.";
    CONFIRM_VALUES_MISSING: "knowledge",
        "`gearcam confirm --undelivered`: gearcam did not hear the job's delivery, so the plan's values may not be what ran, and the values that ran were not given.",
        "Give the cutting speed and feed that really ran (`--cutting-speed`, `--feed`).";
    COUPLING_RATIO: "template (path check)",
        "Path check finding: a gearbox coupling differs from the model's ratio or factors, or a unit is coupled again in another way.",
        "The program was not sent; report it with the job file, since the template and the model disagree.";
    COVERAGE_FAILED: "model",
        "The coverage check of a spiral face found a point of the face outside the tool's disc all along the path (an uncut ring or island), or a groove's measured pitch is off.",
        "Lower the step-over or check the overtravels; the error names the worst point.";
    CROWNING_RANGE: "model",
        "The crowning amount is not between 0 and half the face width.",
        "Correct `gear.crowning.amount_mm` (typically 0.01 to 0.05 mm).";
    CSV_ROW: "knowledge",
        "A row of the CSV file cannot be read (for example, it has the wrong number of cells).",
        "Fix the row named in the error and import again; nothing was imported.";
    CSV_UNREADABLE: "knowledge (`gearcam kb import`)",
        "The file given to `gearcam kb import` is not UTF-8 CSV text (a binary or mis-encoded file); got says where it stops reading. Nothing was imported.",
        "Give the CSV file of the library (`gearcam kb export LIBRARY` writes one to start from).";
    CUTS_RANGE: "model",
        "The number of cuts is outside 1 to 6.",
        "Correct `process.cuts`.";
    CUTTING_SPEED_RANGE: "model",
        "The cutting speed is not positive.",
        "Correct `process.cutting_speed_m_min`, or leave it out for the knowledge base to propose one.";
    CUT_DEPTH: "model",
        "The cut depth is not positive, or cuts the root deeper than the whole depth plus the machine's allowance.",
        "Correct `process.depth_mm`, or leave it out to use the theoretical depth.";
    DATA_DIR_NOT_WRITABLE: "station (`gearcam` commands with a data directory)",
        "The data directory (`--data`, else `GEARCAM_DATA`, else `./gearcam-data`) cannot be made or written by this user; got is the directory, the message the operating system's reason. Nothing was read or changed.",
        "Give `--data` or `GEARCAM_DATA` a directory you can write, or change the directory's owner or permissions.";
    DEPTH_UNCOUPLED: "template (path check)",
        "Path check finding: the hob moves into the contact zone while the gearbox is uncoupled or the hob is stopped, or stops there.",
        "The program was not sent; correct the template so it couples and starts the hob before the cut.";
    DIE_RANGE: "model",
        "A `[die]` value is outside what gearcam cuts: teeth (5 to 1000), module, pressure angle, shift, coefficients, tolerances, thickness, or a pinion cutter without its teeth.",
        "Correct the field; expected gives the range.";
    DUPLICATE_ID: "knowledge",
        "The library already has a record with this key.",
        "Change it with `gearcam kb edit`, or add the record under a new id.";
    DWELL_RANGE: "model",
        "The worm-wheel dwell is negative or not a number.",
        "Correct `gear.worm_wheel.dwell_rev` (0 or more revolutions).";
    ENCODE_FAILED: "station, knowledge, model",
        "A message could not be encoded for the bus or the journal; this is a bug.",
        "Report it with the service's log.";
    END_AT_A: "template (path check)",
        "Path check finding: the program does not end at the start point A, or not with the end code.",
        "The program was not sent; correct the template's last moves and end code.";
    ENVELOPE: "template (path check)",
        "Path check finding: the hob, swept as a solid along a move, enters the table, the fixture or the tailstock.",
        "The program was not sent; check the fixture and the machine's envelope, or correct the template.";
    ENVELOPE_COLLISION: "model",
        "The hob's run-out below the gear would reach the machine's table or the fixture.",
        "Raise the gear on a taller fixture, use a shorter hob, or give the real `gear.fixture_diameter_mm`.";
    FACE_WIDTH_RANGE: "model",
        "The face width is not a positive length.",
        "Correct `gear.face_width_mm`.";
    FEED_LIMIT: "template (path check)",
        "Path check finding: a feed above the machine's largest axial feed, or a feed move without a feed.",
        "The program was not sent; lower the feed or correct the template.";
    FEED_RANGE: "model",
        "The axial feed per revolution is not positive, or not below the helix lead of a helical gear.",
        "Correct `process.feed_mm_per_rev`, or leave it out for the knowledge base to propose one.";
    FEED_RATE_LIMIT: "model",
        "A computed radial feed move is faster than the machine's feed limit.",
        "Lower the radial feed per revolution or the cutting speed.";
    FEED_RATE_RANGE: "model",
        "A radial, tangential or finishing feed per revolution is not positive.",
        "Correct the feed field named in the error.";
    FIELD_INVALID: "knowledge",
        "A knowledge-base field has a value of the wrong type or out of range (a machine profile included).",
        "Give a value as the error's expected says; `gearcam kb libraries` lists every field.";
    FIELD_MISSING: "knowledge",
        "A required knowledge-base field has no value, or an add request carries no record.",
        "Give the field; `gearcam kb libraries` marks the required ones.";
    FINISH_ALLOWANCE_RANGE: "model",
        "The finish allowance is not between 0 and the whole tooth depth.",
        "Correct `process.finish_allowance_mm` (typically 0.1 to 0.5 mm).";
    FLANK_UNDERCUT: "model (warning)",
        "The generating tool undercuts the involute (few teeth, a negative shift, or the small end of a cone): its straight flank reaches past where the line of action touches the base circle. A wire outline follows the undercut fillet up to where it crosses the involute; a hobbed gear is warned from the hob's basic rack (tip radius 0.38·mn).",
        "Nothing, if the drawing asks for the undercut gear; else raise the profile shift.";
    GEAR_MISSING: "knowledge",
        "The job has no `[gear]` section, and its part number is not in the workpiece library.",
        "Add the `[gear]` section, or add the part with `gearcam kb add workpieces` and name it in `[job] part_number`.";
    GROOVE_RANGE: "model",
        "A planar spiral groove's value is out of range: a pitch not above the tool's diameter (the turns would overlap: a face, not a groove), no turns, or more turns than fit before the centre.",
        "Correct the field named in the error; expected says the range.";
    HASH_MISMATCH: "agent",
        "The program text does not match its SHA-256 hash; it was damaged on the way.",
        "Submit the job again; if it repeats, check the network and the sender.";
    HELIX_HAND_MISSING: "model",
        "A helical gear has no helix hand.",
        "Add `helix_hand` (right or left) to `[gear]`.";
    HELIX_RANGE: "model",
        "The helix angle is not strictly between -90° and 90°.",
        "Correct `gear.helix_angle_deg` (0 for a spur gear).";
    HOB_AMBIGUOUS: "knowledge",
        "The job gives both a library hob id and inline hob data.",
        "Give either `hob.id` or the inline hob data, not both.";
    HOB_CLEARANCE: "template (path check)",
        "Path check finding: the hob, swept as a solid along a rapid move, enters a blank.",
        "The program was not sent; correct the template's rapid moves or the safety distance.";
    HOB_FIELD_MISSING: "knowledge",
        "The job's inline hob data lacks a field (starts, od_mm, module_mm, lead_angle_deg, hand or length_mm).",
        "Add the missing `hob.*` field, or give `hob.id` from the library instead.";
    HOB_LEAD_ANGLE_RANGE: "model",
        "The hob lead angle is not between 0° and 45°.",
        "Correct the hob's `lead_angle_deg` (in the job or the tool library).";
    HOB_LENGTH_RANGE: "model",
        "The hob length is not a positive length.",
        "Correct the hob's `length_mm` (in the job or the tool library).";
    HOB_MODULE_RANGE: "model",
        "The hob module is not a positive length.",
        "Correct the hob's `module_mm` (in the job or the tool library).";
    HOB_OD_LIMIT: "model",
        "The hob outside diameter is larger than the machine's hob head takes.",
        "Choose a smaller hob or another machine.";
    HOB_OD_RANGE: "model",
        "The hob outside diameter is not a positive length.",
        "Correct the hob's `od_mm` (in the job or the tool library).";
    HOB_OD_TOO_SMALL: "model",
        "The hob outside diameter is below d0 + 2·(ha* + c*)·mn0, so the hob cannot reach the gear's root.",
        "Check the hob's OD and lead angle, or choose another hob.";
    HOB_PRESSURE_ANGLE_RANGE: "model",
        "The hob pressure angle is not between 0° and 45°.",
        "Correct the hob's `pressure_angle_deg` (in the job or the tool library).";
    HOB_RPM_LIMIT: "model",
        "The computed hob speed is above the machine's limit.",
        "Lower `process.cutting_speed_m_min` or use a hob of larger diameter.";
    HOB_STARTS_RANGE: "model",
        "The hob has fewer than one start.",
        "Correct the hob's `starts` (in the job or the tool library).";
    HOB_TOO_SHORT_FOR_SHIFT: "model",
        "The hob is shorter than its active length, so it cannot shift.",
        "Leave `[process.shift]` out or use a longer hob.";
    ID_MISMATCH: "knowledge",
        "An add query's record has a key that differs from the id in the query's key.",
        "Make the record's key and the id in the query key the same.";
    INTERNAL_ERROR: "knowledge, model, template",
        "The stage's handler panicked on this job; this is a bug.",
        "Report it with the job file and the service's log.";
    INVALID_AXIS_NAME: "template",
        "An axis name in the machine profile is not a valid 840D identifier, or two axes share a name.",
        "Correct the machine's axes in the knowledge base (`gearcam kb edit machines`).";
    INVALID_COUPLING: "template",
        "The model's gearbox ratio z0/z has a zero term; the model stage should have refused the job.",
        "Report it as a bug, with the job file.";
    INVALID_PART_NUMBER: "station",
        "The job's part number is empty, longer than 64 characters or has a line break; it names the program and its history at the machine.",
        "Give the part (drawing) number as on the drawing, on one line.";
    INVALID_PROGRAM_NAME: "knowledge, template",
        "The program name breaks the machine's control's naming rule: the job's own (`job.program_name`), or one made from the part number. The knowledge service checks it before it plans, the template service when it names the program, by the same rule; the message states the rule.",
        "Give the job a name the control accepts in `[job] program_name` (docs/programs.md, program names and files).";
    JOB_CANCELLED: "station, agent",
        "A person cancelled the job before it was delivered (`gearcam cancel`); got says who. The job ends `cancelled`, and the agent never stores its program after.",
        "Nothing, or submit the job again under a new id.";
    JOB_FILE_INVALID: "station",
        "The job file is not valid TOML, or a value has the wrong type.",
        "Fix the job file at the line the message names.";
    JOB_FILE_MISSING_KEY: "station",
        "The job file lacks a required key.",
        "Add the key; for `[gear]` keys you may instead leave the whole section out and name a library part number.";
    JOB_FILE_NOT_FOUND: "station",
        "The job file named on the command line does not exist; got is the path.",
        "Check the path (relative to the working directory), e.g. examples/spur_840d.toml.";
    JOB_FILE_UNKNOWN_KEY: "station",
        "The job file has a key gearcam does not know (often a typo).",
        "Correct or remove the key; the error lists the expected ones.";
    JOB_FILE_UNREADABLE: "station",
        "The job file cannot be read.",
        "Check the path and the file's permissions.";
    JOB_FINAL: "station",
        "The job to cancel has ended already (delivered, failed or superseded); got gives its state.",
        "Nothing to cancel; a delivered program is changed at the machine with `gearcam program rollback` or by a new job.";
    JOB_ID_EXISTS: "station",
        "The job id is already journaled with a different job spec.",
        "Use a new job id; a resubmission must carry the same spec.";
    JOB_ID_MISMATCH: "knowledge, model, template, agent",
        "A message's job id differs from the job id in its key.",
        "Fix the sender so that key and message name the same job.";
    JOB_NOT_JOURNALED: "agent",
        "The agent was sent a program of a job the station has not journaled for its machine (or one that failed); it stores only programs of journaled jobs.",
        "Submit the job through the planning station; a program sent to the agent directly is never stored.";
    JOB_STATE: "knowledge",
        "The job cannot be confirmed in its state: it is not delivered yet, already confirmed, or refused by a later stage (no program was delivered for it).",
        "Confirm a job once, after delivery; pass `--undelivered` with the values that ran for a job cut from a program delivered another way; a refused job is fixed and submitted again.";
    JOB_SUPERSEDED: "agent",
        "An operator adopted the edit at the machine of the program this job waited to replace (`gearcam program resolve --adopt`); got names the adopted version and who. The job ends `superseded` and is never delivered over the edit.",
        "Nothing, if the edit is to stay; for gearcam's program, submit the job again (a new job, under a new id).";
    JOURNAL_ERROR: "station",
        "The station could not read or write its job journal.",
        "See the station's log; check the journal's database file and disk.";
    KB_WRONG_KEY: "knowledge",
        "A knowledge-base change (add, edit, remove) was asked on a read key (gearcam/v1/kb/...), or a read on a change key (gearcam/v1/kb-changes/...); the access control grants the two to different users.",
        "Ask changes on gearcam/v1/kb-changes/{user}/{library}[/{id}] (the change is recorded as `{user}`'s), reads on gearcam/v1/kb/{library}[/{id}].";
    KEY_IMMUTABLE: "knowledge",
        "An edit tried to change a record's key.",
        "Add a new record with the new key and remove the old one.";
    KNOWLEDGE_BASE_ERROR: "knowledge",
        "The knowledge base could not be read or written.",
        "Check the knowledge service's log and its database file.";
    MACHINE_FAMILY: "knowledge",
        "A job was sent to a machine of another part family (a spiral face milling or wire EDM job to a hobbing machine, or the reverse).",
        "Choose a machine of the job's family; expected lists them.";
    MACHINE_MODULE_LIMIT: "model",
        "The gear's module is outside the machine's module range.",
        "Choose another machine for this gear.";
    MACHINE_RANGE: "model",
        "A spiral job's spindle speed, feed or tool-centre reach is beyond the milling machine's limit, or a wire job's plate thickness or contour is beyond the wire machine's.",
        "Lower the cutting speed or feed given in `[milling]`, or use a machine that reaches; expected gives the limit.";
    MACHINE_SETTING_RANGE: "model",
        "A setting, axis sense, envelope value or parameter block of the machine profile is out of range.",
        "Correct the machine profile in the knowledge base (`gearcam kb edit machines`).";
    MALFORMED_MESSAGE: "any",
        "A message's bytes are not a gearcam MessagePack envelope of the expected kind.",
        "Fix the sender; the message was dropped.";
    MATE_RANGE: "model",
        "The mating gear's data is out of range: teeth below 1, a profile shift that is not a number, or a centre distance that is not positive.",
        "Correct `[gear.mate]`.";
    MCODE_PAIR: "template (path check)",
        "Path check finding: a switched function (support, fixture, coolant, conveyor, mist) is switched off without being on, on twice, or still on at the end.",
        "The program was not sent; correct the template's M codes.";
    MESSAGE_TOO_LARGE: "any",
        "A message is larger than its reader accepts.",
        "Fix the sender; the message was dropped.";
    MISSING_FIELD: "knowledge",
        "A section given inline lacks a field it needs (e.g. an inline `[mill]` without its kind, radius or flutes).",
        "Add the field named, or name a library record instead.";
    MISSING_ID: "knowledge",
        "A get, edit or remove query has no record id in its key.",
        "Query `gearcam/v1/kb/{library}/{id}`.";
    MISSING_SECTION: "knowledge",
        "A spiral face milling job has neither a `[face]` nor a `[groove]` section, or a wire EDM job no `[die]`.",
        "Describe the face (outer_radius_mm, inner_radius_mm, depth_mm, material), the groove, or the die (part, module_mm, teeth, thickness_mm, material).";
    MODEL_NOT_JOURNALED: "station",
        "The station's journal has no model of the job: the model service has not computed it yet, or the job failed before its model (the station journals each job's model as the model service publishes it).",
        "Wait for the job's `modelled` event (`gearcam status JOB`); a job that failed before its model has no picture.";
    MODEL_UNKNOWN: "agent",
        "The agent checks every program again against the model the model service published for the job and has not seen that model (it started after it was published); the job waits.",
        "Nothing: the station re-drives the job, the model is published again and the program is checked and stored.";
    MODULE_RANGE: "model",
        "The gear's normal module is not a positive length.",
        "Correct `gear.module_mm`.";
    NOT_FINITE: "station (job file, and every request at the bus), model",
        "A value that must be a number (a job file's number, profile shift, OD correction, fixture height) is NaN or infinite.",
        "Give a finite value for the field named.";
    NOT_FOUND: "knowledge",
        "The library has no record with this id.",
        "Use an existing id; `gearcam kb list LIBRARY` lists them.";
    NO_CONFLICT: "agent",
        "A resolution was asked for a program that has no edit at the machine to resolve (the file is gearcam's current version, or it was deleted and --adopt was asked).",
        "Look at `gearcam program history`; --replace writes gearcam's version back over a deleted file.";
    NO_CSV: "knowledge",
        "This library cannot be imported or exported as CSV.",
        "Use workpieces, hobs, cases or materials, which have CSV.";
    NO_CUTTING_DATA: "knowledge",
        "The knowledge base has neither similar milling cases nor milling data for the job's material group, and the job gives no cutting speed and feed; or no wire-data row for the wire's material and the plate's group (nor an `any` row).",
        "Give `[milling]` cutting_speed_m_min and feed_per_tooth_mm, or add milling data for the group (gearcam kb add milling-data); for wire, add a wire-data row.";
    NO_MATCHING_HOB: "knowledge",
        "No hob in the tool library fits the gear (base pitch, accuracy class, usable length).",
        "Add a fitting hob with `gearcam kb add hobs`, or give the hob inline.";
    NO_RETRACT: "template, agent (spiral replay)",
        "Spiral verification finding: the replayed program ends below the safe height.",
        "The program was not sent; report it, the generator is at fault.";
    NO_TOOL: "knowledge",
        "No tool of the library fits: no end mill of the groove's width, or an empty tool library.",
        "Add a tool (gearcam kb add mills) or give `[mill]`.";
    PARSE: "template (path check)",
        "Path check finding: a program line lies outside the NC subset gearcam emits, or its arithmetic fails.",
        "The program was not sent; correct the template line named in the error.";
    PASS_DEPTHS: "template, agent (spiral replay)",
        "Spiral verification finding: the replayed program cuts at other depths, or in another number of passes, than the model.",
        "The program was not sent; report it, the generator is at fault.";
    PATH_CHECK_FAILED: "template, agent",
        "The path check of the rendered program found a line that breaks a rule; the rule is in expected, one error per finding.",
        "The program was not sent; look up the rule in this table and correct the template or the job.";
    PLUNGE_IN_MATERIAL: "template, agent (spiral replay)",
        "Spiral verification finding: a feed move goes down below the face where the tool's disc overlaps the face's material, so the pass would start inside it.",
        "The program was not sent; report it, the generator is at fault.";
    POSITION_TRAVEL_LIMIT: "model",
        "A computed position or move end lies outside the machine's X or Z travel.",
        "Check the blank and hob diameters, fixture height, face width and safety distance, as the message says.";
    PREDICTED_GRADE: "template (virtual hobbing, warning)",
        "The gear the program's virtual run cuts grades worse than the drawing's ISO 1328-1 class; the warning names the deviation that sets the grade.",
        "Check the deviation named: a finer feed, more hob gashes or a better-mounted hob; `gearcam check` shows every deviation.";
    PRESSURE_ANGLE_RANGE: "model",
        "The gear's normal pressure angle is not between 0° and 45°.",
        "Correct `gear.pressure_angle_deg` (usually 20°).";
    PROGRAM_CHANGED_AT_MACHINE: "agent",
        "The program file at the machine was changed or created there since gearcam stored it; the agent kept the file, and the job waits.",
        "Review the edit, then `gearcam program resolve NAME --machine M --adopt` (the edit becomes the current version) or `--replace` (gearcam's version goes back, the edit is kept in the history). After --replace the waiting job is delivered; after --adopt it ends superseded (submit it again for gearcam's program).";
    PROGRAM_FORM: "knowledge, model, template",
        "The program form asked for (`[milling]` or `[wire]` program) is not one the machine's control runs, or a turned wire program (`[wire]` whole = false) is asked of a control that cannot turn a section of blocks.",
        "Choose one of the forms expected lists, or another machine.";
    PROGRAM_NAME_TAKEN: "agent",
        "The program name is held at the machine by a program of another part; the agent does not replace it. The error names both parts and a free name.",
        "Give the job its own name (`program_name` in `[job]`), e.g. the free one the error offers.";
    PROGRAM_TOO_LARGE: "template, agent",
        "The program is larger than the size limit (when rendered, or when stored).",
        "Check the template for runaway repetition.";
    QUANTITY_RANGE: "model",
        "The job's quantity is below 1.",
        "Correct `job.quantity`.";
    RAPID_CLEARANCE: "template (path check)",
        "Path check finding: a rapid move passes through the zone where the hob can touch the blank.",
        "The program was not sent; correct the template's rapid moves or the safety distance.";
    RAPID_IN_MATERIAL: "template, agent (spiral replay)",
        "Spiral verification finding: the replayed program moves at rapid below the face, or across X/Y while the tool is below it (no retract first).",
        "The program was not sent; report it, the generator is at fault.";
    REPLAY_FAILED: "template, agent (spiral replay)",
        "Spiral verification finding: the program could not be replayed by the Macro B / LinuxCNC subset interpreter (a syntax error, an unset variable, a runaway loop); the line is given.",
        "The program was not sent; report it, the generator is at fault.";
    REVISION_CONFLICT: "agent",
        "This job revision was already stored with different content.",
        "Send the changed program as a new revision.";
    SAFETY_RANGE: "model",
        "The safety distance is negative.",
        "Correct `process.safety_mm`.";
    SECTION_FAMILY: "station, knowledge",
        "A job file carries a section of another part family (`[gear]` in a spiral face milling job, `[face]` in a hobbing job, `[die]` in either; refused when the file is read), or a spiral job both `[face]` and `[groove]`, or a family's planner was handed another family's job.",
        "Remove the section, or set `[job]` family to the job's family.";
    SETUP: "template (path check)",
        "Path check finding: the program does not set unit, work offset, diameter mode or G-code system as the machine profile needs, or writes a parameter outside the profile's free block.",
        "The program was not sent; correct the template's header or the machine profile.";
    SHIFT_RANGE: "model",
        "A hob-shift setting is out of range: a step that is not positive, zero parts per step, or a start or end outside the usable hob length.",
        "Correct the `process.shift` field named, or leave it out.";
    SIMULATED_GEAR_WRONG: "template (virtual hobbing)",
        "The program's virtual run cuts a visibly wrong gear: it cannot be measured as the drawing's gear (a wrong tooth count, a gap not cut), its helix is beyond class 11 (a wrong hand or lead), or its pitch deviations are beyond the drawing's class.",
        "The program was not sent; `gearcam check` shows the simulated gear's deviations: correct the template, the machine profile's senses or the gearbox data.";
    SIMULATION_UNSAFE: "template (virtual hobbing)",
        "The program's virtual run found a hazard: the hob in the blank during a rapid, cutting with the gearbox off or in a wrong ratio, the hob meeting the table, fixture or tailstock, depth or face width not reached, a shift or a coupling that lands a cut in other gaps.",
        "The program was not sent; the error names the line and what happens there.";
    SPEED_LIMIT: "template (path check)",
        "Path check finding: a hob speed, or the table speed it gives, is above the machine's limit.",
        "The program was not sent; lower the cutting speed or correct the template.";
    SPIRAL_DEVIATION: "template, agent (spiral replay)",
        "Spiral verification finding: the replayed path strays further from the model's spiral than the tolerance, sampled at 20,001 points per pass.",
        "The program was not sent; report it, the generator is at fault.";
    SPIRAL_ENDS: "template, agent (spiral replay)",
        "Spiral verification finding: a replayed pass starts or ends away from the model's spiral.",
        "The program was not sent; report it, the generator is at fault.";
    SPIRAL_RANGE: "model",
        "A spiral face-milling value is out of range: a radius not positive, an inner radius not below the outer one, a tool larger than the face, a step-over of the tool's diameter or more (it leaves material between the turns), a negative overtravel.",
        "Correct the field named in the error; expected says the range.";
    STATION_UNREACHABLE: "agent",
        "The agent could not ask the planning station whether the job is journaled; the job waits.",
        "Start the station (`gearcam station` or `gearcam up`); the job is delivered at its next re-drive.";
    STEP_OVER_LARGE: "model (warning)",
        "The spiral's step-over is over 90 % of the tool's diameter: neighbouring turns overlap little, and a tool a little under its nominal size would leave a ring.",
        "Check the tool's real diameter, or lower the step-over.";
    STORE_INDEX_ERROR: "agent",
        "The agent could not read or write its program index, or found a bad row in it.",
        "See the agent's log; check the store's database file.";
    STORE_IO_ERROR: "agent",
        "The agent could not read or write a file in the machine's program directory.",
        "Check the program directory's path, permissions and free space.";
    SWIVEL_LIMIT: "model",
        "The computed swivel angle is above the machine's limit.",
        "Use a hob of the same hand as the gear's helix, or another machine.";
    TABLE_RPM_LIMIT: "model",
        "The computed table speed of the job or of a rough cut is above the machine's limit.",
        "Lower `process.cutting_speed_m_min` or use a hob with fewer starts.";
    TEETH_RANGE: "model",
        "The gear has fewer than one tooth, or more than any hobbed gear (10,000).",
        "Correct `gear.teeth`.";
    TEMPLATE_FUEL_EXHAUSTED: "template",
        "The template used up its budget of expression steps while rendering.",
        "Check the template for runaway loops.";
    TEMPLATE_LIBRARY_UNREADABLE: "template (`gearcam check`)",
        "The template library (templates.db in the data directory) cannot be read.",
        "Check `--data` and the templates.db file in it.";
    TEMPLATE_NOT_FOUND: "template",
        "There is no template for the gear's class on the machine's controller.",
        "Choose a machine whose controller has a template for this class, or add the template to the library.";
    TEMPLATE_RENDER_FAILED: "template",
        "The template failed while rendering this model.",
        "Correct the template at the line the message names.";
    TIP_TOO_SHARP: "model",
        "The gear's tooth is thinner than 0.2·m at the tip circle (or comes to a point): the profile shift or addendum is too large for the teeth.",
        "Lower `[die]` profile_shift or addendum_coef.";
    TOOL_RANGE: "knowledge",
        "An inline tool's value is out of range (radius not positive, no flutes, a corner radius above the radius).",
        "Correct the field named.";
    TOO_MANY_JOBS: "station",
        "An agent's question about the jobs it is to store (`gearcam/v1/station/journaled/{machine}`) names more jobs than the station answers at once; expected gives the most.",
        "Ask about a large group in parts; gearcam's agent never asks about more at once.";
    TRAVEL_LIMIT: "template (path check)",
        "Path check finding: an X or Z target lies outside the machine's travel, or a swivel goes beyond its limit.",
        "The program was not sent; check the machine profile's travel or correct the template.";
    UNDERCUT_TOO_DEEP: "model",
        "A barely undercut gear: the generating rack's flank reaches just past the interference point, and the fillet ends off the involute without crossing it; the outline there (the involute's other branch) is not modelled. The scan of z 6–18, x −0.5…+0.8 finds it only at the edge of the undercut region.",
        "Change the profile shift by a tenth (or the teeth by one) so the gear is clearly undercut or not.";
    UNEXPECTED_REPLY: "station, agent (seen by the CLI)",
        "The station or agent answered a query with another kind of reply than expected; it may run another version.",
        "Run the same gearcam version on the station, the agents and this computer.";
    UNIT_COLLISION: "model",
        "While cutting one unit of a multi-gear part, the hob would cut into another unit.",
        "Move the units apart with `z_offset_mm`, or plan a run-out groove.";
    UNIT_HOB_INCOMPLETE: "model",
        "A unit's inline hob data lacks a field (starts, od_mm, module_mm, lead_angle_deg, hand or length_mm).",
        "Add the field, or leave `[units.hob]` empty to use the job's hob.";
    UNIT_HOB_UNRESOLVED: "model",
        "A unit names a library hob other than the job's; only the job's hob is taken from the library so far.",
        "Give this unit's hob data inline.";
    UNIT_RANGE: "model",
        "A unit of a multi-gear part overlaps the unit below it, or its offset is not a number.",
        "List units from the bottom up and correct the unit's `z_offset_mm`.";
    UNKNOWN_FIELD: "knowledge",
        "A record, an edit path or a CSV column names a field the library does not have.",
        "Use the fields `gearcam kb libraries` lists.";
    UNKNOWN_HOB: "knowledge",
        "The job's `hob.id` is not in the tool library.",
        "Use a hob id from `gearcam kb list hobs`, or give the hob data inline.";
    UNKNOWN_JOB: "station, knowledge",
        "The job is unknown: the station's journal has no such job (status), or the knowledge base did not plan it (confirm).",
        "Check the job id with `gearcam jobs` or `gearcam kb list jobs`.";
    UNKNOWN_LIBRARY: "knowledge",
        "The knowledge base has no library of this name.",
        "Use classes, workpieces, hobs, machines, cases, jobs, materials or weights.";
    UNKNOWN_MACHINE: "station, knowledge",
        "The job names a machine the knowledge base does not have.",
        "Pick one of the machines listed by `gearcam kb list machines`, or add the machine.";
    UNKNOWN_PROGRAM: "agent",
        "The machine's program store has never held a program of this name.",
        "Check the name with `gearcam program history --machine MACHINE`.";
    UNKNOWN_SCHEMA_VERSION: "any",
        "A message carries a schema version this reader does not understand.",
        "Run the same gearcam version on every station, service and agent.";
    UNKNOWN_TOOL: "knowledge",
        "The `[mill]` id names no tool of the library.",
        "Name a tool of gearcam kb list mills, or give the tool inline.";
    UNKNOWN_VERSION: "agent",
        "The program store has no such version (seq) of this program.",
        "Pick a version listed by `gearcam program history`.";
    UNKNOWN_WIRE: "knowledge",
        "The wire named in `[wire]` (or the machine's default wire) is not in the knowledge base's wires.",
        "Name a wire of `gearcam kb list wires`, or add it.";
    UNSAFE_APPROACH: "template, agent (spiral replay)",
        "Spiral verification finding: the replayed program moves in X/Y before a move has taken the tool up to the safe height (where the tool starts is not known).",
        "The program was not sent; report it, the generator is at fault.";
    WIRE_CLOSURE: "template, agent (wire replay)",
        "Wire verification finding: the replayed program does not close on itself within the flank's tolerance, or does not go once round the part.",
        "The program was not sent; report it, the generator is at fault.";
    WIRE_DEVIATION: "model, template, agent (wire replay)",
        "Wire verification finding: the replayed wire path strays from the outline set off by the wire further than the flank's or the fillet's tolerance, even with the tightest fit.",
        "Loosen the tolerances or choose the ISO form (its 0.1 µm resolution leaves the fit more room); expected and got give the figures.";
    WIRE_LEAD_CROSSES_PART: "model, template, agent (wire replay)",
        "Wire verification finding: the replayed lead-in or lead-out runs through the part that is kept (the die plate, the punch), or starts from a hole inside it; the message names the block and the place.",
        "The program was not sent; report it, the generator is at fault.";
    WIRE_LEAD_OUT: "model, template, agent (wire replay)",
        "Wire verification finding: the replayed program, every block run as the control runs it (lead-in, turned sections, lead-out), does not end at its start hole; the message says where it ends.",
        "The program was not sent; report it, the generator is at fault.";
    WIRE_REPLAY_FAILED: "model, template, agent (wire replay)",
        "Wire verification finding: the program could not be read back or replayed (a block the reader refuses, or the control's offset impossible on it).",
        "The program was not sent; report it, the generator is at fault.";
    WIRE_TOO_THICK: "model",
        "A concave place of the part (the punch's root fillet, the die's flank near its base) has a smaller radius than the wire's radius plus spark gap: the wire cannot follow it. The message names the tooth and the place.",
        "Choose a thinner wire (`[wire]` wire or wire_diameter_mm).";
    WORKPIECE_INCOMPLETE: "knowledge",
        "The workpiece library's record of the part lacks data its gear class needs.",
        "Give the job's `[gear]` section in full, or complete the workpiece record.";
    WORKPIECE_OD_LIMIT: "model",
        "The blank is larger than the machine's largest workpiece.",
        "Choose a larger machine.";
    WRONG_DIALECT: "agent",
        "The program is written for another controller dialect than the agent's machine has.",
        "Make the machine's dialect in the knowledge base match the agent's configuration.";
    WRONG_MACHINE: "agent",
        "The program is for another machine than the one this agent serves.",
        "Check the agent's configured machine id.";
    WRONG_MESSAGE_KIND: "any",
        "A message holds another kind of message than its key promises.",
        "Fix the sender to put the right kind of message on this key.";
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stage names a [`CodeInfo::stage`] may list.
    const STAGES: [&str; 6] = ["station", "knowledge", "model", "template", "agent", "any"];

    fn upper_snake(code: &str) -> bool {
        code.starts_with(|c: char| c.is_ascii_uppercase())
            && !code.ends_with('_')
            && !code.contains("__")
            && code
                .chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
    }

    #[test]
    fn codes_are_unique_sorted_and_upper_snake() {
        for pair in CATALOGUE.windows(2) {
            assert!(
                pair[0].code.as_str() < pair[1].code.as_str(),
                "not sorted or not unique: {} then {}",
                pair[0].code,
                pair[1].code
            );
        }
        let bad: Vec<&str> = CATALOGUE
            .iter()
            .map(|c| c.code.as_str())
            .filter(|c| !upper_snake(c))
            .collect();
        assert!(bad.is_empty(), "not UPPER_SNAKE: {bad:?}");
    }

    #[test]
    fn every_meaning_and_action_is_a_sentence() {
        for c in CATALOGUE {
            for (what, text) in [("meaning", c.meaning), ("action", c.action)] {
                assert!(
                    !text.trim().is_empty() && text.ends_with('.'),
                    "{}: the {what} must be non-empty and end with a period: {text:?}",
                    c.code
                );
            }
            assert!(
                !c.meaning.contains('|') && !c.action.contains('|'),
                "{}: no | (docs/errors.md is a table)",
                c.code
            );
        }
    }

    #[test]
    fn every_stage_names_known_stages() {
        for c in CATALOGUE {
            let names = c.stage.split(" (").next().unwrap_or_default();
            for name in names.split(", ") {
                assert!(
                    STAGES.contains(&name),
                    "{}: unknown stage {name:?} in {:?}",
                    c.code,
                    c.stage
                );
            }
        }
    }

    #[test]
    fn lookup_finds_every_code_and_only_those() {
        for (i, c) in CATALOGUE.iter().enumerate() {
            assert_eq!(lookup(c.code.as_str()), Some(c));
            assert_eq!(
                c.code as usize, i,
                "{} is not at its variant's index",
                c.code
            );
            assert_eq!(c.code.info(), c);
            assert_eq!(Code::parse(c.code.as_str()), Some(c.code));
        }
        assert_eq!(lookup("BASE_PITCH_MISMATCH").unwrap().stage, "model");
        assert_eq!(Code::BASE_PITCH_MISMATCH.as_str(), "BASE_PITCH_MISMATCH");
        assert!(lookup("NO_SUCH_CODE").is_none());
        assert!(lookup("").is_none());
        assert_eq!(Code::parse("NO_SUCH_CODE"), None);
    }

    #[test]
    fn a_code_travels_as_its_text() {
        let bytes = rmp_serde::to_vec(&Code::CUT_DEPTH).unwrap();
        assert_eq!(
            rmp_serde::from_slice::<String>(&bytes).unwrap(),
            "CUT_DEPTH"
        );
        assert_eq!(
            rmp_serde::from_slice::<Code>(&bytes).unwrap(),
            Code::CUT_DEPTH
        );
        let unknown = rmp_serde::to_vec("NO_SUCH_CODE").unwrap();
        let err = rmp_serde::from_slice::<Code>(&unknown).unwrap_err();
        assert!(err.to_string().contains("NO_SUCH_CODE"), "{err}");
    }
}
