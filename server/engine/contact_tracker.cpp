#include "contact_tracker.hpp"

#include <algorithm>

namespace lpss::engine {

void ContactTracker::count(const ContactRecord& contact, const SectorKey& where, int delta) {
    auto key = std::make_pair(contact.a, contact.b);
    auto it = touching_.find(key);
    int count = it == touching_.end() ? 0 : it->second;
    auto [change, first] = changed_pairs_.try_emplace(key, PairChange{count, contact, where, delta > 0});
    if (!first && delta > 0 && !change->second.seen) {
        change->second = PairChange{change->second.before, contact, where, true};
    }
    count += delta;
    if (count > 0) {
        touching_[key] = count;
    } else if (it != touching_.end()) {
        touching_.erase(it);
    }
}

void ContactTracker::forget(std::vector<ContactRecord>& pairs, const SectorKey& where, BodyId id) {
    auto involved = [id](const ContactRecord& c) { return c.a == id || c.b == id; };
    for (const ContactRecord& c : pairs) {
        if (involved(c)) count(c, where, -1);
    }
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(), involved), pairs.end());
}

void ContactTracker::forget_all(std::vector<ContactRecord>& pairs, const SectorKey& where) {
    for (const ContactRecord& c : pairs)
        count(c, where, -1);
    pairs.clear();
}

void ContactTracker::replace(const SectorKey& where, const std::vector<ContactRecord>& old_pairs,
                             const std::vector<ContactRecord>& new_pairs) {
    auto before = [](const ContactRecord& x, const ContactRecord& y) {
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    };
    std::size_t i = 0, j = 0;
    while (i < old_pairs.size() || j < new_pairs.size()) {
        if (j == new_pairs.size() || (i < old_pairs.size() && before(old_pairs[i], new_pairs[j]))) {
            count(old_pairs[i++], where, -1);
        } else if (i == old_pairs.size() || before(new_pairs[j], old_pairs[i])) {
            count(new_pairs[j++], where, +1);
        } else {
            ++i, ++j;
        }
    }
}

void ContactTracker::make_events() {
    events_.clear();
    for (const auto& [key, change] : changed_pairs_) {
        bool now = touching_.count(key) != 0;
        if (change.before == 0 && now) {
            ContactEvent event;
            event.kind = ContactEvent::Kind::Begin;
            event.a = key.first;
            event.b = key.second;
            event.point = SectorPosition{change.where, change.record.point};
            event.normal = change.record.normal.cast<double>();
            event.impulse = change.record.impulse;
            events_.push_back(event);
        } else if (change.before > 0 && !now) {
            ContactEvent event;
            event.kind = ContactEvent::Kind::End;
            event.a = key.first;
            event.b = key.second;
            events_.push_back(event);
        }
    }
    changed_pairs_.clear();
    std::sort(events_.begin(), events_.end(), [](const ContactEvent& x, const ContactEvent& y) {
        if (x.kind != y.kind) return x.kind < y.kind;
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    });
}

int ContactTracker::sectors_seeing(BodyId a, BodyId b) const {
    auto it = touching_.find(std::make_pair(a, b));
    return it == touching_.end() ? 0 : it->second;
}

}  // namespace lpss::engine
