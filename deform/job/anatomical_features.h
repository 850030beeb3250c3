// AnatomicalFeatures: the features a caller selects on top of the sweep deformation (paper
// §4.3–4.4) — skin folding, bone protrusion, volume preservation, muscle bulge — and whole-body
// contact (deform/features/skin_contact.h; beyond the paper). DeformJob
// (deform_job.h) applies them; sweepctl and the daemon pass the same selection, so the same
// selection gives the same vertices bit for bit.
// to_string: "folding,protrusion" style list of the selected features ("" when none).
#pragma once

#include <string>

namespace sweepd::deform {

struct AnatomicalFeatures {
  bool folding = false, protrusion = false, volume = false, bulge = false, contact = false;
  bool any() const { return folding || protrusion || volume || bulge || contact; }
  // Folding, protrusion or contact: the features that move vertices after the sweep deformation.
  bool collision() const { return folding || protrusion || contact; }
  bool operator==(const AnatomicalFeatures&) const = default;
};

std::string to_string(const AnatomicalFeatures& features);

}  // namespace sweepd::deform
