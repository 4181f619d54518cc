// The built-in label legends (declared in legend.hpp). Class names are the datasets' standard
// lists; colours come from one palette so that every legend's ids get distinct colours.
#include <functional>
#include <map>

#include "semfuse/core/legend.hpp"

namespace semfuse {
namespace {

// Distinct colours for ids 0..255: the bits of the id are spread over the high bits of R, G and
// B (bit 0 -> R, bit 1 -> G, bit 2 -> B, next three one bit lower, ...), so neighbouring ids
// differ strongly and no two ids below 256 share a colour. Id 0 is black.
std::array<uint8_t, 3> paletteColor(unsigned id) {
  std::array<uint8_t, 3> rgb{0, 0, 0};
  for (int shift = 7; shift >= 0 && id != 0; --shift, id >>= 3) {
    for (unsigned channel = 0; channel < 3; ++channel) {
      if (id & (1u << channel)) rgb[channel] = static_cast<uint8_t>(rgb[channel] | (1u << shift));
    }
  }
  return rgb;
}

LabelLegend fromNames(std::string name, const std::vector<const char*>& names, std::vector<LabelId> background) {
  LabelLegend legend;
  legend.name = std::move(name);
  for (std::size_t i = 0; i < names.size(); ++i) {
    legend.labels.push_back({static_cast<LabelId>(i), names[i], paletteColor(static_cast<unsigned>(i))});
  }
  legend.background_ids = std::move(background);
  return legend;
}

// ADE20K SceneParsing objectInfo150 (first name of each class), shifted by one: 0 = other.
LabelLegend ade20k() {
  return fromNames("ade20k",
                   {"other",
                    "wall",
                    "building",
                    "sky",
                    "floor",
                    "tree",
                    "ceiling",
                    "road",
                    "bed",
                    "windowpane",
                    "grass",
                    "cabinet",
                    "sidewalk",
                    "person",
                    "earth",
                    "door",
                    "table",
                    "mountain",
                    "plant",
                    "curtain",
                    "chair",
                    "car",
                    "water",
                    "painting",
                    "sofa",
                    "shelf",
                    "house",
                    "sea",
                    "mirror",
                    "rug",
                    "field",
                    "armchair",
                    "seat",
                    "fence",
                    "desk",
                    "rock",
                    "wardrobe",
                    "lamp",
                    "bathtub",
                    "railing",
                    "cushion",
                    "base",
                    "box",
                    "column",
                    "signboard",
                    "chest of drawers",
                    "counter",
                    "sand",
                    "sink",
                    "skyscraper",
                    "fireplace",
                    "refrigerator",
                    "grandstand",
                    "path",
                    "stairs",
                    "runway",
                    "case",
                    "pool table",
                    "pillow",
                    "screen door",
                    "stairway",
                    "river",
                    "bridge",
                    "bookcase",
                    "blind",
                    "coffee table",
                    "toilet",
                    "flower",
                    "book",
                    "hill",
                    "bench",
                    "countertop",
                    "stove",
                    "palm",
                    "kitchen island",
                    "computer",
                    "swivel chair",
                    "boat",
                    "bar",
                    "arcade machine",
                    "hovel",
                    "bus",
                    "towel",
                    "light",
                    "truck",
                    "tower",
                    "chandelier",
                    "awning",
                    "streetlight",
                    "booth",
                    "television receiver",
                    "airplane",
                    "dirt track",
                    "apparel",
                    "pole",
                    "land",
                    "bannister",
                    "escalator",
                    "ottoman",
                    "bottle",
                    "buffet",
                    "poster",
                    "stage",
                    "van",
                    "ship",
                    "fountain",
                    "conveyer belt",
                    "canopy",
                    "washer",
                    "plaything",
                    "swimming pool",
                    "stool",
                    "barrel",
                    "basket",
                    "waterfall",
                    "tent",
                    "bag",
                    "minibike",
                    "cradle",
                    "oven",
                    "ball",
                    "food",
                    "step",
                    "tank",
                    "trade name",
                    "microwave",
                    "pot",
                    "animal",
                    "bicycle",
                    "lake",
                    "dishwasher",
                    "screen",
                    "blanket",
                    "sculpture",
                    "hood",
                    "sconce",
                    "vase",
                    "traffic light",
                    "tray",
                    "ashcan",
                    "fan",
                    "pier",
                    "crt screen",
                    "plate",
                    "monitor",
                    "bulletin board",
                    "shower",
                    "radiator",
                    "glass",
                    "clock",
                    "flag"},
                   {0});
}

// Pascal VOC 2012 segmentation classes.
LabelLegend voc() {
  return fromNames("voc", {"background", "aeroplane", "bicycle",     "bird",  "boat",        "bottle", "bus",
                           "car",        "cat",       "chair",       "cow",   "diningtable", "dog",    "horse",
                           "motorbike",  "person",    "pottedplant", "sheep", "sofa",        "train",  "tvmonitor"},
                   {0});
}

// NYU Depth v2 40-class mapping (Gupta et al.), 0 = unlabeled.
LabelLegend nyu40() {
  return fromNames("nyu40", {"unlabeled",  "wall",    "floor",       "cabinet",        "bed",
                             "chair",      "sofa",    "table",       "door",           "window",
                             "bookshelf",  "picture", "counter",     "blinds",         "desk",
                             "shelves",    "curtain", "dresser",     "pillow",         "mirror",
                             "floor mat",  "clothes", "ceiling",     "books",          "refrigerator",
                             "television", "paper",   "towel",       "shower curtain", "box",
                             "whiteboard", "person",  "night stand", "toilet",         "sink",
                             "lamp",       "bathtub", "bag",         "otherstructure", "otherfurniture",
                             "otherprop"},
                   {0});
}

// The built-in synthetic room. These ids are a contract with common/synthetic: never renumber.
LabelLegend synthetic() {
  LabelLegend legend;
  legend.name = "synthetic";
  legend.labels = {
      {0, "unlabeled", {0, 0, 0}},    {1, "floor", {150, 110, 70}},  {2, "wall", {200, 200, 190}},
      {3, "ceiling", {90, 160, 230}}, {4, "table", {230, 150, 30}},  {5, "chair", {220, 40, 60}},
      {6, "box", {60, 180, 75}},      {7, "sphere", {145, 60, 200}}, {8, "cabinet", {20, 120, 120}},
  };
  legend.background_ids = {0};
  return legend;
}

const std::map<std::string, std::function<LabelLegend()>>& registry() {
  static const std::map<std::string, std::function<LabelLegend()>> legends = {
      {"ade20k", ade20k}, {"voc", voc}, {"nyu40", nyu40}, {"synthetic", synthetic}};
  return legends;
}

}  // namespace

std::optional<LabelLegend> builtinLegend(const std::string& name) {
  const auto it = registry().find(name);
  if (it == registry().end()) return std::nullopt;
  return it->second();
}

std::vector<std::string> builtinLegendNames() {
  std::vector<std::string> names;
  for (const auto& entry : registry()) names.push_back(entry.first);
  return names;
}

}  // namespace semfuse
