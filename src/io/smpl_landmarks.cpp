// Landmarks and measurement definitions for SMPL's 6890-vertex topology, compiled in so an
// installed binary needs no data folder. The same text is landmarks/smpl.json (which documents
// the sources); test_smpl_loader checks the two agree, so edit both together.
#include "caliper/io/model_files.h"

namespace caliper {

const std::string& smpl_landmarks_json() {
  static const std::string json = R"json(
{
  "topology": "SMPL (also SMPL-H): 6890 vertices, 13776 faces",
  "vertex_count": 6890,
  "landmarks": {
    "vertex": 412,
    "temple_left": 166,
    "neck_front": 3050,
    "acromion_left": 3011,
    "acromion_right": 6470,
    "thelion_left": 3042,
    "thelion_right": 6489,
    "omphalion": 3501,
    "navel_back": 3022,
    "pubic_bone": 3145,
    "crotch": 1210,
    "inseam_point": 3149,
    "thigh_left": 947,
    "calf_left": 1103,
    "ankle_left": 3325,
    "heel_left": 3458,
    "heel_right": 6858,
    "toe_left": 3216,
    "toe_right": 6617,
    "biceps_right": 4855,
    "forearm_right": 5197,
    "wrist_left": 2241,
    "wrist_right": 5559,
    "dactylion_left": 2445,
    "dactylion_right": 5905
  },
  "sources": {
    "SMPL-Anthropometry (D. Bojanić, landmark_definitions.py, SMPL_LANDMARK_INDICES)": [
      "vertex (HEAD_TOP)", "temple_left (HEAD_LEFT_TEMPLE)", "neck_front (NECK_ADAM_APPLE)",
      "acromion_left/right (LEFT/RIGHT_SHOULDER)", "thelion_left/right (LEFT/RIGHT_NIPPLE)",
      "omphalion (BELLY_BUTTON)", "navel_back (BACK_BELLY_BUTTON)", "pubic_bone (PUBIC_BONE)",
      "crotch (CROTCH)", "inseam_point (INSEAM_POINT)", "thigh_left (LEFT_THIGH)", "calf_left (LEFT_CALF)",
      "ankle_left (LEFT_ANKLE)", "heel_left/right (LEFT/RIGHT_HEEL)", "biceps_right (RIGHT_BICEP)",
      "forearm_right (RIGHT_FOREARM)", "wrist_left/right (LEFT/RIGHT_WRIST)"
    ],
    "smplx Python package (vertex_ids.py, 'smplh' table, shared by SMPL's topology)": [
      "dactylion_left/right (lmiddle/rmiddle fingertips)", "toe_left/right (LBigToe/RBigToe)"
    ]
  },
  "measurements": [
    {"name": "stature", "kind": "height", "landmarks": ["vertex"], "plane_normal": "y",
     "description": "Top of the head above the floor"},
    {"name": "weight", "kind": "weight", "landmarks": [], "plane_normal": "y",
     "description": "a * volume + b (paper section 3.4.2)"},
    {"name": "span", "kind": "length", "landmarks": ["dactylion_left", "dactylion_right"], "plane_normal": "y",
     "description": "Middle fingertip to middle fingertip in the T-pose"},
    {"name": "wrist_span", "kind": "length", "landmarks": ["wrist_left", "wrist_right"], "plane_normal": "y",
     "description": "Wrist to wrist in the T-pose"},
    {"name": "crotch_height", "kind": "height", "landmarks": ["crotch"], "plane_normal": "y",
     "description": "Crotch above the floor (inseam height)"},
    {"name": "chest_height", "kind": "height", "landmarks": ["thelion_left"], "plane_normal": "y",
     "description": "Nipple above the floor"},
    {"name": "waist_height", "kind": "height", "landmarks": ["omphalion"], "plane_normal": "y",
     "description": "Navel above the floor"},
    {"name": "biacromial_breadth", "kind": "length", "landmarks": ["acromion_left", "acromion_right"], "plane_normal": "y",
     "description": "Shoulder to shoulder (acromion to acromion)"},
    {"name": "arm_length", "kind": "length", "landmarks": ["acromion_right", "wrist_right"], "plane_normal": "y",
     "description": "Right shoulder (acromion) to right wrist"},
    {"name": "hip_breadth", "kind": "breadth", "landmarks": ["pubic_bone"], "plane_normal": "y",
     "description": "Breadth of the horizontal section at the pubic bone"},
    {"name": "chest_breadth", "kind": "front_breadth", "landmarks": ["thelion_left"], "plane_normal": "y",
     "description": "Breadth of the horizontal section at nipple height, across its front half"},
    {"name": "chest_depth", "kind": "depth", "landmarks": ["thelion_left"], "plane_normal": "y",
     "description": "Depth of the horizontal section at nipple height"},
    {"name": "waist_breadth", "kind": "breadth", "landmarks": ["omphalion"], "plane_normal": "y",
     "description": "Breadth of the horizontal section at the navel"},
    {"name": "waist_depth", "kind": "depth", "landmarks": ["omphalion"], "plane_normal": "y",
     "description": "Depth of the horizontal section at the navel"},
    {"name": "chest_circumference", "kind": "circumference", "landmarks": ["thelion_left"], "plane_normal": "y",
     "description": "Tape around the chest at nipple height"},
    {"name": "waist_circumference", "kind": "circumference", "landmarks": ["omphalion"], "plane_normal": "y",
     "description": "Tape around the waist at the navel"},
    {"name": "buttock_circumference", "kind": "circumference", "landmarks": ["pubic_bone"], "plane_normal": "y",
     "description": "Tape around the hips at the pubic bone"},
    {"name": "neck_circumference", "kind": "circumference", "landmarks": ["neck_front"], "plane_normal": "y",
     "description": "Tape around the neck at the Adam's apple"},
    {"name": "thigh_circumference", "kind": "circumference", "landmarks": ["thigh_left"], "plane_normal": "y",
     "description": "Tape around the left thigh"},
    {"name": "calf_circumference", "kind": "circumference", "landmarks": ["calf_left"], "plane_normal": "y",
     "description": "Tape around the left calf"},
    {"name": "ankle_circumference", "kind": "circumference", "landmarks": ["ankle_left"], "plane_normal": "y",
     "description": "Tape around the left ankle"},
    {"name": "biceps_circumference", "kind": "circumference", "landmarks": ["biceps_right"], "plane_normal": "x",
     "description": "Tape around the right upper arm (T-pose arm, section across the arm)"},
    {"name": "forearm_circumference", "kind": "circumference", "landmarks": ["forearm_right"], "plane_normal": "x",
     "description": "Tape around the right forearm"},
    {"name": "wrist_circumference", "kind": "circumference", "landmarks": ["wrist_right"], "plane_normal": "x",
     "description": "Tape around the right wrist"}
  ],
  "notes": [
    "Vertex ids are public facts from the two sources listed; none was guessed.",
    "Left out because no public id is known here with confidence: lateral hip points (hip_left/right), cervicale, axilla, suprasternale, elbow (radiale), stylion, knee, lateral malleolus, head breadth/length points. Measurements needing them (e.g. forearm_length, knee_height, head_breadth) are therefore not defined for SMPL.",
    "Hip-level sections (hip_breadth, buttock_circumference) use the pubic bone vertex, the level SMPL-Anthropometry uses for hip circumference. The paper (section 3.1) measures hip width at inseam height.",
    "SMPL's rest pose is a T-pose with the arms close to horizontal, so arm sections use a plane normal to X.",
    "The heels and toes are given for foot placement; foot_length is not defined because the heel vertex is not at the foot's rear-most point along its axis.",
    "This file is compiled into the library (src/io/smpl_landmarks.cpp); a unit test checks the two agree."
  ]
}
)json";
  return json;
}

}  // namespace caliper
