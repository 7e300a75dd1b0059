/// @file contact_params.cpp
/// Registry of contact parts; equations in contact_params.hpp / contact_law.hpp.
#include "ssdem/contact_params.hpp"

#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "common/status.hpp"

namespace ssdem {

void ContactPartRegistry::add(ContactPartInfo info) {
  if (parts_.count(info.name)) throw std::invalid_argument("contact part '" + info.name + "' registered twice");
  std::string key = info.name;
  parts_.emplace(std::move(key), std::move(info));
}

const ContactPartInfo* ContactPartRegistry::find(const std::string& name) const {
  auto it = parts_.find(name);
  return it == parts_.end() ? nullptr : &it->second;
}

std::vector<std::string> ContactPartRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [k, v] : parts_) out.push_back(k);
  return out;
}

void ContactPartRegistry::declare(common::Schema& schema) const {
  std::string all;
  for (const auto& [k, v] : parts_) all += (all.empty() ? "" : ", ") + k;
  schema.add_string("contact.parts", std::string("normal,damping,tangential,rolling,twisting"),
                    "comma-separated contact parts (styles) to enable; available: " + all +
                        ". 'normal' is mandatory; parts not listed cost nothing");
  schema.add_real("contact.beta", 0.5, "1", 0.0, 10.0,
                  "shape parameter beta of the rolling/twisting contact size a = beta*Rbar "
                  "(Zhang et al. 2017)",
                  true);
  schema.add_bool("contact.resolve_edges", true,
                  "resolve contact onset and release within the step (edge impulses of the normal spring "
                  "and dashpot, contact_law.hpp): e_n error second order in dt (false: the plain "
                  "step, as pkdgrav, first order: 6.7e-3 at 50.5 steps per contact, e_n = 0.55)");
  for (const auto& [k, v] : parts_) schema.include("contact." + k, v.schema);
}

ContactParams ContactPartRegistry::resolve(const common::Scene& scene) const {
  ContactParams p;
  std::string list = scene.string("contact.parts");
  std::stringstream ss(list);
  std::string item;
  int normal = 0;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b == std::string::npos) continue;
    item = item.substr(b, e - b + 1);
    const ContactPartInfo* info = find(item);
    if (!info) {
      std::string all;
      for (const auto& n : names()) all += (all.empty() ? "" : ", ") + n;
      throw common::InputError(scene.where("contact.parts") + ": unknown contact part '" + item +
                               "' (available: " + all + ")");
    }
    if (info->slot == PartSlot::normal) ++normal;
    p.parts |= info->flag;
    info->read(scene, "contact." + item + ".", p);
  }
  if (normal != 1)
    throw common::InputError(scene.where("contact.parts") +
                             ": exactly one normal law ('normal' or 'hertz') must be listed");
  for (const auto& [name, info] : parts_) {
    if (!info.flag || !(p.parts & info.flag) || (p.parts & info.requires_parts) == info.requires_parts) continue;
    std::string need;
    for (const auto& [n2, i2] : parts_)
      if (i2.flag & info.requires_parts) need += (need.empty() ? "'" : ", '") + n2 + "'";
    throw common::InputError(scene.where("contact.parts") + ": '" + name + "' needs " + need + "'");
  }
  if ((p.parts & kPartHertz) && !(p.E > 0.0))
    throw common::InputError(scene.where("contact.hertz.E") + ": the 'hertz' law needs Young's modulus E > 0");
  p.beta = scene.real("contact.beta");
  p.resolve_edges = scene.boolean("contact.resolve_edges");
  return p;
}

void register_builtin_contact_parts(ContactPartRegistry& reg) {
  TableInfo::for_each([&](auto* tag) {
    using P = std::remove_pointer_t<decltype(tag)>;
    ContactPartInfo i;
    i.name = P::name;
    i.flag = P::flag;
    i.requires_parts = P::requires_parts;
    i.slot = P::slot;
    i.help = P::help;
    P::declare(i.schema);
    i.read = [](const common::Scene& s, const std::string& pre, ContactParams& p) { P::read(s, pre, p); };
    reg.add(std::move(i));
  });
}

double ContactParams::contact_time(double mu, double Rbar) const {
  if (parts & kPartHertz) {
    const double Estar = E / (2.0 * (1.0 - nu * nu));
    return hertz_contact_time(mu, (4.0 / 3.0) * Estar * std::sqrt(Rbar), vmax);
  }
  const double xi = (parts & kPartDamping) ? damping_ratio(en) : 0.0;
  return M_PI * std::sqrt(mu / (kn * (1.0 - xi * xi)));
}

ContactParams gravel_preset(double kn) {
  ContactParams p;
  p.parts = kPartDamping | kPartTangential | kPartRolling | kPartTwisting;
  p.kn = kn;
  p.en = 0.55;
  p.et = 0.55;
  p.mu_s = 1.0;
  p.mu_r = 1.05;
  p.mu_t = 1.3;
  p.beta = 0.5;
  p.kt_over_kn = 2.0 / 7.0;
  return p;
}

}  // namespace ssdem
