// Contact events. Each sector keeps the pairs that touched at its last step; a pair may be seen by
// several sectors (an original and the clone of its partner on each side of a border), so the world
// counts the sectors reporting each pair. The events of a frame compare each changed pair's count
// before and after the frame: from zero, it began; to zero, it ended. A body changing sector is seen
// by its new sector in the same frame as it leaves the old one, and so causes no event. A sector not
// stepped keeps its pairs: nothing in it moved.
#include <algorithm>

#include "world_impl.hpp"

namespace lpss {

using engine::ContactRecord;
using engine::Sector;

void World::Impl::count_contact(const ContactRecord& contact, const SectorKey& where, int delta) {
    auto key = std::make_pair(contact.a, contact.b);
    auto it = touching.find(key);
    int count = it == touching.end() ? 0 : it->second;
    auto [change, first] = changed_pairs.try_emplace(key, PairChange{count, contact, where, delta > 0});
    if (!first && delta > 0 && !change->second.seen) {
        change->second = PairChange{change->second.before, contact, where, true};
    }
    count += delta;
    if (count > 0) {
        touching[key] = count;
    } else if (it != touching.end()) {
        touching.erase(it);
    }
}

void World::Impl::forget_contacts(Sector& sector, BodyId id) {
    auto involved = [id](const ContactRecord& c) { return c.a == id || c.b == id; };
    for (const ContactRecord& c : sector.contacts) {
        if (involved(c)) count_contact(c, sector.key, -1);
    }
    sector.contacts.erase(std::remove_if(sector.contacts.begin(), sector.contacts.end(), involved),
                          sector.contacts.end());
}

void World::Impl::merge_contacts() {
    auto before = [](const ContactRecord& x, const ContactRecord& y) {
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    };
    for (engine::SectorId id : step_set) {
        Sector* sector = &sectors.at(id);
        const std::vector<ContactRecord>& old_pairs = sector->contacts;
        const std::vector<ContactRecord>& new_pairs = sector->fresh_contacts;
        std::size_t i = 0, j = 0;
        while (i < old_pairs.size() || j < new_pairs.size()) {
            if (j == new_pairs.size() || (i < old_pairs.size() && before(old_pairs[i], new_pairs[j]))) {
                count_contact(old_pairs[i++], sector->key, -1);
            } else if (i == old_pairs.size() || before(new_pairs[j], old_pairs[i])) {
                count_contact(new_pairs[j++], sector->key, +1);
            } else {
                ++i, ++j;
            }
        }
        sector->contacts.swap(sector->fresh_contacts);
        if (sector->awake) wake(*sector);
    }

    events.clear();
    for (const auto& [key, change] : changed_pairs) {
        bool now = touching.count(key) != 0;
        if (change.before == 0 && now) {
            ContactEvent event;
            event.kind = ContactEvent::Kind::Begin;
            event.a = key.first;
            event.b = key.second;
            event.point = SectorPosition{change.where, change.record.point};
            event.normal = change.record.normal.cast<double>();
            event.impulse = change.record.impulse;
            events.push_back(event);
        } else if (change.before > 0 && !now) {
            ContactEvent event;
            event.kind = ContactEvent::Kind::End;
            event.a = key.first;
            event.b = key.second;
            events.push_back(event);
        }
    }
    changed_pairs.clear();
    std::sort(events.begin(), events.end(), [](const ContactEvent& x, const ContactEvent& y) {
        if (x.kind != y.kind) return x.kind < y.kind;
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    });
}

}  // namespace lpss
