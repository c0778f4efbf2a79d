/* A reader of lpss/sector_frames built with another vendor's DDS (Eclipse Cyclone DDS, Debian's
 * cyclonedds-dev) from idl/lpss.idl by its own IDL compiler: what another vendor's program sees of an lpss
 * cluster. It reads until it has seen frame LAST and WRITERS samples without data (a writer's disposal or
 * unregistration, which carry only the key), or for at most SECONDS, then prints what it took: samples with
 * data and without, the workers and the newest frame.
 * usage: cyclone_sector_reader DOMAIN SECONDS LAST WRITERS */
#include <stdio.h>
#include <stdlib.h>

#include "dds/dds.h"
#include "lpss.h"

#define BATCH 64

int main(int argc, char** argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: %s DOMAIN SECONDS LAST WRITERS\n", argv[0]);
        return 2;
    }
    const dds_domainid_t domain = (dds_domainid_t)atoi(argv[1]);
    const double seconds = atof(argv[2]);
    const unsigned long long last = strtoull(argv[3], NULL, 10);
    const unsigned long long writers = strtoull(argv[4], NULL, 10);
    dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
    if (participant < 0) {
        fprintf(stderr, "cannot create a participant: %s\n", dds_strretcode(-participant));
        return 1;
    }
    dds_entity_t topic =
        dds_create_topic(participant, &lpss_wire_SectorFrame_desc, "lpss/sector_frames", NULL, NULL);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 8192);
    dds_entity_t reader = dds_create_reader(participant, topic, qos, NULL);
    dds_delete_qos(qos);
    if (topic < 0 || reader < 0) {
        fprintf(stderr, "cannot create the reader\n");
        return 1;
    }
    void* samples[BATCH] = {NULL};
    dds_sample_info_t infos[BATCH];
    unsigned long long with_data = 0, without_data = 0, bodies = 0, newest = 0;
    unsigned long workers = 0; /* bit per worker id below 32 */
    const dds_time_t end = dds_time() + (dds_time_t)(seconds * 1e9);
    while (dds_time() < end && !(newest >= last && without_data >= writers)) {
        const int n = dds_take(reader, samples, infos, BATCH, BATCH);
        if (n < 0) {
            fprintf(stderr, "take failed: %s\n", dds_strretcode(-n));
            return 1;
        }
        for (int i = 0; i < n; ++i) {
            if (!infos[i].valid_data) {
                ++without_data;
                continue;
            }
            const lpss_wire_SectorFrame* f = (const lpss_wire_SectorFrame*)samples[i];
            ++with_data;
            bodies += f->bodies._length;
            if (f->frame > newest) newest = f->frame;
            if (f->worker < 32) workers |= 1ul << f->worker;
        }
        if (n > 0) dds_return_loan(reader, samples, n);
        if (n == 0) dds_sleepfor(DDS_MSECS(5));
    }
    printf("samples with data %llu, without %llu, bodies %llu, newest frame %llu, writers", with_data,
           without_data, bodies, newest);
    for (unsigned w = 0; w < 32; ++w)
        if (workers & (1ul << w)) printf(" %u", w);
    printf("\n");
    dds_delete(participant);
    return 0;
}
