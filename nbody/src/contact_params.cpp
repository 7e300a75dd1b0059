/// @file contact_params.cpp
/// Registry of contact parts; equations in contact_params.hpp / contact_law.hpp.
#include "ssdem/contact_params.hpp"

#include <sstream>
#include <stdexcept>

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
  for (const auto& [k, v] : parts_) schema.include("contact." + k, v.schema);
}

ContactParams ContactPartRegistry::resolve(const common::Scene& scene) const {
  ContactParams p;
  std::string list = scene.string("contact.parts");
  std::stringstream ss(list);
  std::string item;
  bool normal = false;
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
    if (info->flag == 0) normal = true;
    p.parts |= info->flag;
    info->read(scene, "contact." + item + ".", p);
  }
  if (!normal)
    throw common::InputError(scene.where("contact.parts") + ": the 'normal' part is mandatory");
  if ((p.parts & kPartTwisting) && !(p.parts & kPartTangential))
    throw common::InputError(scene.where("contact.parts") +
                             ": 'twisting' needs 'tangential' (its limit is mu_t mu_s a |F_N|)");
  p.beta = scene.real("contact.beta");
  return p;
}

void register_builtin_contact_parts(ContactPartRegistry& reg) {
  {
    ContactPartInfo i;
    i.name = "normal";
    i.flag = 0;
    i.help = "linear normal spring F = -k_n x n (Schwartz+2012 eq. 3)";
    i.schema.add_real("kn", 0.0, "N/m", 0.0, 1e30,
                      "normal spring constant k_n; 0 = from the k_n rule (contact.vmax, "
                      "contact.overlap_fraction; dt_rule.hpp)");
    i.read = [](const common::Scene& s, const std::string& pre, ContactParams& p) {
      p.kn = s.real(pre + "kn");
    };
    reg.add(std::move(i));
  }
  {
    ContactPartInfo i;
    i.name = "damping";
    i.flag = kPartDamping;
    i.help = "normal dashpot from the restitution coefficient e_n (Schwartz+2012 eq. 15)";
    i.schema.add_real("en", 0.55, "1", 0.0, 1.0, "normal coefficient of restitution e_n", true);
    i.read = [](const common::Scene& s, const std::string& pre, ContactParams& p) {
      p.en = s.real(pre + "en");
    };
    reg.add(std::move(i));
  }
  {
    ContactPartInfo i;
    i.name = "tangential";
    i.flag = kPartTangential;
    i.help = "tangential spring with history and Coulomb cap mu_s (Schwartz+2012 eqs 6-7, 17-19)";
    i.schema.add_real("kt_over_kn", 2.0 / 7.0, "1", 0.0, 10.0, "k_t / k_n", true);
    i.schema.add_real("et", 0.55, "1", 0.0, 1.0,
                      "tangential damping setting e_t (C_t from e_t with k_t; used only with the "
                      "damping part)",
                      true);
    i.schema.add_real("mu_s", 1.0, "1", 0.0, 100.0, "static friction coefficient mu_s");
    i.schema.add_choice("slip", SlipRule::coulomb, kSlipRules,
                        "slip rule: coulomb (rescale to mu_s|F_N|) or pkdgrav (zero S, "
                        "min(mu_s|F_N|, C_t|u_t|))");
    i.read = [](const common::Scene& s, const std::string& pre, ContactParams& p) {
      p.kt_over_kn = s.real(pre + "kt_over_kn");
      p.et = s.real(pre + "et");
      p.mu_s = s.real(pre + "mu_s");
      p.slip = s.choice(pre + "slip", kSlipRules);
    };
    reg.add(std::move(i));
  }
  {
    ContactPartInfo i;
    i.name = "rolling";
    i.flag = kPartRolling;
    i.help = "rolling spring-dashpot-slider, k_r = k_n a^2, limit mu_r a |F_N| (Zhang+2017)";
    i.schema.add_real("mu_r", 1.05, "1", 0.0, 100.0, "rolling friction coefficient mu_r");
    i.read = [](const common::Scene& s, const std::string& pre, ContactParams& p) {
      p.mu_r = s.real(pre + "mu_r");
    };
    reg.add(std::move(i));
  }
  {
    ContactPartInfo i;
    i.name = "twisting";
    i.flag = kPartTwisting;
    i.help = "twisting spring-dashpot-slider, k_q = 2 k_t a^2, limit mu_t mu_s a |F_N| (Zhang+2017)";
    i.schema.add_real("mu_t", 1.3, "1", 0.0, 100.0, "twisting friction coefficient mu_t");
    i.read = [](const common::Scene& s, const std::string& pre, ContactParams& p) {
      p.mu_t = s.real(pre + "mu_t");
    };
    reg.add(std::move(i));
  }
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
